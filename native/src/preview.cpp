// The live drag's preview: while the user drags an object, each step must show something
// within a tenth of a second, and a real update takes seconds. What the eye follows during a
// drag is the direct light -- the shadow the object casts and the light on its own faces --
// so a step re-traces only that, from the output's own trace: the lamps' shadow rays and the
// transfers from emitting senders of the points a moved box can touch, and of the moved
// objects' points carried with them. Bounced light stays as solved until the drag pauses and
// the update runs. Nothing here changes the solution: the dragged objects' Embree placements
// and hierarchy geometry are put back as they were, bit for bit (only the ray counter grows).
#include <algorithm>
#include <atomic>
#include <cmath>
#include <stdexcept>

#include <tbb/enumerable_thread_specific.h>

#include "final_gather_trace.h"
#include "radiosity/lights.h"
#include "radiosity/parallel.h"
#include "radiosity/solver.h"
#include "radiosity/transfer.h"

namespace radiosity {

namespace {

// Whether a shadow ray of some lamp from x (normal n) may meet one of `clips`: a point or spot
// light's segment hull; the sun's rays toward the sun disk; the sky's, anywhere in front.
bool lamps_meet(const SceneDesc& scene, const Hierarchy& h, const Vec3& x, const Vec3& n, const std::vector<Aabb>& clips) {
    for (const LightDesc& d : scene.lights()) {
        if (!(d.intensity.max() > 0)) continue;
        Aabb lb;
        if (d.type == LightDesc::Type::Point || d.type == LightDesc::Type::Spot) {
            const Vec3 q = h.to_internal(d.position);
            const double r = d.radius / h.unit;
            lb.lo = q - Vec3{r, r, r};
            lb.hi = q + Vec3{r, r, r};
        } else if (d.type == LightDesc::Type::Sun) {
            // Past the scene's far end toward the sun, as wide as the disk is there.
            const double far = 4.0 * h.scene_diag;
            const Vec3 q = x - d.direction * far;
            const double r = far * std::tan(0.5 * std::min(d.angle, 3.0)) + 1e-9;
            lb.lo = q - Vec3{r, r, r};
            lb.hi = q + Vec3{r, r, r};
        } else {
            for (const Aabb& c : clips)
                for (int k = 0; k < 8; ++k) {
                    const Vec3 corner{(k & 1) ? c.hi.x : c.lo.x, (k & 2) ? c.hi.y : c.lo.y, (k & 4) ? c.hi.z : c.lo.z};
                    if (dot(corner - x, n) > 0) return true;
                }
            continue;
        }
        if (hull_meets(x, lb, clips)) return true;
    }
    return false;
}

// The hierarchy's geometry that placing objects rewrites (Hierarchy::place_object): their
// nodes, the clusters above them, their primitives and the surface tables. Saved before a
// preview places them, put back after: placing them again from the rest geometry would not
// give the same bits (children's normals are their parents' when built, recomputed when placed).
class SavedGeometry {
public:
    SavedGeometry(const Hierarchy& h, const std::vector<int>& objects) {
        std::vector<char> seen(h.nodes.size(), 0);
        auto keep = [&](int id) {
            if (id < 0 || seen[size_t(id)]) return;
            seen[size_t(id)] = 1;
            const Node& n = h.nodes[size_t(id)];
            nodes_.push_back({id, n.poly, n.normal, n.center, n.box, n.radius, n.area, n.rho_max, n.W});
        };
        for (int o : objects) {
            for (int id : h.object_nodes(o)) keep(id);
            for (int a = h.object_node[size_t(o)] >= 0 ? h.nodes[size_t(h.object_node[size_t(o)])].parent : h.root; a >= 0;
                 a = h.nodes[size_t(a)].parent)
                keep(a);
            for (size_t i = 0; i < h.prims.size(); ++i)
                if (h.prims[i].object == o) {
                    prims_.emplace_back(i, h.prims[i].poly);
                    for (int side : {h.prims[i].front, h.prims[i].back})
                        if (side >= 0)
                            for (int id : subtree(h, h.surfaces[size_t(side)].root)) keep(id);
                }
        }
        surface_geom_ = h.surface_geom;
        area_prefix_ = h.area_prefix;
        facing_summary_ = h.facing_summary;
    }
    void restore(Hierarchy& h) {
        for (const Saved& v : nodes_) {
            Node& n = h.nodes[size_t(v.id)];
            n.poly = v.poly;
            n.normal = v.normal;
            n.center = v.center;
            n.box = v.box;
            n.radius = v.radius;
            n.area = v.area;
            n.rho_max = v.rho_max;
            n.W = v.W;
        }
        for (const auto& [i, poly] : prims_) h.prims[i].poly = poly;
        h.surface_geom.swap(surface_geom_);
        h.area_prefix.swap(area_prefix_);
        h.facing_summary.swap(facing_summary_);
    }

private:
    static std::vector<int> subtree(const Hierarchy& h, int root) {
        std::vector<int> out{root};
        for (size_t k = 0; k < out.size(); ++k)
            for (int c : h.nodes[size_t(out[k])].children) out.push_back(c);
        return out;
    }
    struct Saved {
        int id;
        Poly poly;
        Vec3 normal, center;
        Aabb box;
        double radius, area, rho_max;
        decltype(Node::W) W;
    };
    std::vector<Saved> nodes_;
    std::vector<std::pair<size_t, Poly>> prims_;
    std::vector<SurfaceGeom> surface_geom_;
    std::vector<double> area_prefix_;
    std::vector<Hierarchy::FacingSummary> facing_summary_;
};

// The lists one thread reuses from point to point in a preview.
struct PreviewScratch {
    std::vector<std::pair<int, float>> fresh, samples;
    std::vector<std::pair<int, bool>> reaching;
    std::vector<std::pair<int, double>> use;
};

// Irradiance / pi at a point gathered afresh from the active links reaching its leaf and the
// lamps, without retraces, closure or near field (a footprint uncovered).
Rgb fresh_irradiance(const FinalGather::Solution& s, const FinalGather::Config& config, const fg::Point& pt,
                     PreviewScratch& scratch, int64_t& rays) {
    // The links reaching the point's leaf (links_reaching), each from the point as trace_point
    // does, without its shadow-edge retraces, closure and near field (a preview's
    // approximation), budgets shared by the light they bring.
    const Hierarchy& h = s.h;
    const int leaf = h.live_element(pt.leaf);
    std::vector<std::pair<int, bool>>& reaching = scratch.reaching;
    std::vector<std::pair<int, double>>& use = scratch.use;
    fg::links_reaching(s, nullptr, leaf, reaching);
    use.clear();
    double total = 0;
    for (const auto& link_own : reaching) {
        const Link& l = s.links[size_t(link_own.first)];
        const Node& src = h.nodes[size_t(l.src)];
        const double w = l.K_unoccluded * std::max(src.Lmax.max(), src.L.max());
        if (!(w > 0)) continue;
        use.emplace_back(link_own.first, w);
        total += w;
    }
    const PointLight lamp = direct_light_at(s.scene, h, s.vis, pt.x, pt.n, false, config.light_samples, pt.seed);
    rays += lamp.rays;
    Rgb E = lamp.E;
    // A quarter of the trace's budget, one ray for the faint: a preview of a footprint, seen
    // while it moves.
    const int budget = std::max(config.rays / 4, config.min_rays);
    std::vector<std::pair<int, float>>& samples = scratch.samples;
    for (const auto& [li, w] : use) {
        const Link& l = s.links[size_t(li)];
        samples.clear();
        PointRayStream rs(s.vis);
        point_transfer(h, rs, l.src, pt.x, pt.n, leaf, fg::ray_share(budget, w, total, 1, budget),
                       fg::transfer_seed(h, pt.seed, l.src), samples);
        for (const auto& [node, sw] : samples) E += h.nodes[size_t(h.live_element(node))].L * double(sw);
        rays += rs.cast;
    }
    return E;
}

// Adds to dE the change of what the point's emitting senders (`emits`, per node) bring it at
// its new place (x, n): each transfer whose rays may meet a moved box, or every one when the
// point or the sender moved, traced again. Returns the transfers re-traced.
int64_t add_emitter_changes(const FinalGather::Solution& s, const FinalGather::Preview& p,
                            const FinalGather::Config& config, const fg::Point& pt, const Vec3& x, const Vec3& n,
                            bool moved, const std::vector<char>& emits, std::vector<std::pair<int, float>>& fresh, Rgb& dE,
                            int64_t& rays) {
    const Hierarchy& h = s.h;
    int64_t transfers = 0;
    for (const fg::Record& r : pt.records) {
        if (!emits[size_t(r.src)]) continue;
        const Node& src = h.nodes[size_t(r.src)];
        // (The hierarchy has the moved objects at their new places: a sender in one, or a
        // cluster holding one, draws other rays now; none replays a recorded outcome.)
        const bool src_moved = (src.object >= 0 && size_t(src.object) < p.moved.size() && p.moved[size_t(src.object)]) ||
                               (size_t(r.src) < p.moved_nodes.size() && p.moved_nodes[size_t(r.src)]);
        if (!moved && !src_moved && !hull_meets(x, src.box, p.clips)) continue;
        const Rgb was = fg::record_light(h, pt, r);
        // trace_point's seed for this transfer (a shadow edge's retrace: +1, a deep
        // penumbra's, with more rays than the budget: +2), so that the rays through no moved
        // box are the ones recorded and replay their outcomes.
        const uint64_t seed =
            fg::transfer_seed(h, pt.seed, r.src) + (r.refined ? (int(r.rays) > config.rays ? 2 : 1) : 0);
        fresh.clear();
        const PointRays recorded = r.outcome();
        PointRayStream rs(s.vis, moved || src_moved ? nullptr : &recorded, &p.clips);
        point_transfer(h, rs, r.src, x, n, pt.leaf, int(r.rays), seed, fresh);
        Rgb now;
        for (const auto& [node, w] : fresh) now += h.nodes[size_t(h.live_element(node))].L * double(w);
        // Through the point's closure factors, as values() weighs this record's samples.
        dE += (now - was) * (r.own ? pt.c_own : pt.c_inherited);
        rays += rs.cast;
        ++transfers;
    }
    return transfers;
}

}  // namespace

std::vector<Rgb> FinalGather::preview(const Solution& s, const Preview& p, PreviewCounts& counts) const {
    if (!traced()) return {};
    const std::vector<fg::Point>& points = impl_->points;
    const Config& config = impl_->config;
    std::vector<Rgb> d(points.size());
    const Hierarchy& h = s.h;
    // Senders that emit: emitting elements and every node above one. Only their transfers
    // are re-traced (a dark sender's light is bounced light, left as solved).
    std::vector<char> emits(h.nodes.size(), 0);
    for (size_t i = 0; i < h.nodes.size(); ++i) {
        const Node& m = h.nodes[i];
        if (m.dead || m.is_cluster() || !(m.emission.max() > 0)) continue;
        for (int a = int(i); a >= 0 && !emits[size_t(a)]; a = h.nodes[size_t(a)].parent) emits[size_t(a)] = 1;
    }
    auto inside_any = [](const std::vector<Aabb>& boxes, const Vec3& x) {
        for (const Aabb& b : boxes)
            if (b.contains(x)) return true;
        return false;
    };
    std::atomic<int64_t> n_points{0}, n_lamps{0}, n_transfers{0}, n_rays{0}, n_uncovered{0}, n_covered{0};
    tbb::enumerable_thread_specific<PreviewScratch> scratch;
    parallel_for(points.size(), config.threads, [&](size_t i) {
        const fg::Point& pt = points[i];
        PreviewScratch& sc = scratch.local();
        if (pt.object < 0 || size_t(pt.object) >= p.moved.size()) return;
        const bool moved = p.moved[size_t(pt.object)] != 0;
        const Vec3 x = moved ? p.carry[size_t(pt.object)].point(pt.x) : pt.x;
        const Vec3 n = moved ? p.carry[size_t(pt.object)].dir(pt.n) : pt.n;
        Rgb dE;
        int64_t rays = 0;
        bool changed = false;
        // The footprint the dragged object leaves: a point it covered (unlit, no record of what
        // it sees) is gathered afresh, roughly; and one it covers now goes unlit.
        if (!moved && p.covered) {
            const int surface = h.nodes[size_t(h.live_element(pt.leaf))].surface;
            if (pt.covered && inside_any(p.clips, x) && !p.covered(surface, x, n)) {
                d[i] = fresh_irradiance(s, config, pt, sc, rays) - impl_->point_value(h, pt, true);
                n_rays += rays;
                ++n_uncovered;
                ++n_points;
                return;
            }
            if (!pt.covered && inside_any(p.now, x) && p.covered(surface, x, n)) {
                d[i] = Rgb{} - impl_->point_value(h, pt, true);
                ++n_covered;
                ++n_points;
                return;
            }
        }
        // (A covered point is sealed too under a closed solid: the footprint's rule above
        // comes first.)
        if (pt.covered || pt.sealed) return;
        if (!s.scene.lights().empty() && (moved || lamps_meet(s.scene, h, x, n, p.clips))) {
            const PointLight lamp = direct_light_at(s.scene, h, s.vis, x, n, false, config.light_samples, pt.seed);
            dE += lamp.E - pt.direct;
            rays += lamp.rays;
            ++n_lamps;
            changed = true;
        }
        const int64_t transfers = add_emitter_changes(s, p, config, pt, x, n, moved, emits, sc.fresh, dE, rays);
        n_transfers += transfers;
        changed = changed || transfers > 0;
        d[i] = dE;
        n_points += changed;
        n_rays += rays;
    }, 8);
    counts.points = n_points;
    counts.lamps = n_lamps;
    counts.transfers = n_transfers;
    counts.rays = n_rays;
    counts.uncovered = n_uncovered;
    counts.covered = n_covered;
    return d;
}

bool FinalGather::corner_value(const Hierarchy& h, int object, size_t corner, bool irradiance, const Rgb& change,
                               Rgb& out) const {
    const int p = corner_point(object, corner);
    if (p < 0) return false;
    out = impl_->point_value(h, impl_->points[size_t(p)], irradiance, change);
    return true;
}

struct Solver::PlacedPolygon {
    Poly poly;
    Vec3 normal;
    Aabb box;
};

std::vector<CornerPatch> Solver::preview(const std::map<int, std::array<double, 16>>& moves,
                                         FinalGather::PreviewCounts* counts) {
    if (!solved_) throw std::logic_error("preview: solve the scene first");
    if (settings_.gather_rays <= 0 || !output_.traced())
        throw std::logic_error("preview: needs the final gather's trace (gather_rays > 0)");
    FinalGather::Preview p;
    std::vector<std::pair<int, Rigid>> placed;
    preview_moves(moves, p, placed);
    // (DirectLight::contact's test, with the moved objects where they are now.)
    const std::vector<PlacedPolygon> polys = placed_polygons(p);
    const double tol = 1e-7 * h_.scene_diag;
    const double inside_tol = 1e-9 * h_.scene_diag;
    p.covered = [&](int surface, const Vec3& x, const Vec3& n) {
        if (surface >= 0 && size_t(surface) < direct_light_.contacts().size())
            for (int t : direct_light_.contacts()[size_t(surface)]) {
                const Node& m = h_.nodes[size_t(h_.surfaces[size_t(t)].root)];
                if (m.object >= 0 && p.moved[size_t(m.object)]) continue;  // where it was
                if (within_edges(m.poly, m.normal, x, inside_tol)) return true;
            }
        for (const PlacedPolygon& q : polys) {
            if (!q.box.contains(x) || dot(q.normal, n) > -1 + 1e-6) continue;
            if (std::fabs(dot(x - q.poly.v[0], q.normal)) > tol) continue;
            if (within_edges(q.poly, q.normal, x, inside_tol)) return true;
        }
        return false;
    };
    // Clusters holding a dragged object (their sampling of surfaces changes with it).
    p.moved_nodes.assign(h_.nodes.size(), 0);
    for (const auto& op : placed) {
        const int top = h_.object_node[size_t(op.first)];
        for (int a = top >= 0 ? h_.nodes[size_t(top)].parent : h_.root; a >= 0; a = h_.nodes[size_t(a)].parent)
            p.moved_nodes[size_t(a)] = 1;
    }
    auto place = [this](int object, const Rigid& q) { vis_->set_object_transform(object, q); };
    std::vector<int> objects;
    for (const auto& op : placed) objects.push_back(op.first);
    // The solution's placements back however the preview ends (Embree's from the same poses:
    // the same floats; the hierarchy's from the saved copy).
    struct Restore {
        Solver* s;
        const std::vector<std::pair<int, Rigid>>& placed;
        const decltype(place)& put;
        SavedGeometry saved;
        ~Restore() {
            if (placed.empty()) return;
            saved.restore(s->h_);
            try {
                for (const auto& op : placed) put(op.first, s->edits_.poses()[size_t(op.first)]);
                s->vis_->commit();
            } catch (...) {
                // An Embree error here leaves rays as the preview placed them: the solution
                // must not be trusted. (Never seen: the same calls succeeded a moment ago.)
                s->solved_ = false;
            }
        }
    } restore{this, placed, place, SavedGeometry(h_, objects)};
    for (const auto& [object, q] : placed) {
        place(object, q);
        h_.place_object(object, q);
    }
    if (!placed.empty()) vis_->commit();

    FinalGather::PreviewCounts k;
    std::vector<CornerPatch> out;
    if (!placed.empty()) {
        const FinalGather::Solution s{scene_, h_, *vis_, links_,
                                      [this](int surface, const Vec3& q) { return direct_light_.contact(h_, surface, q); }, &tri_prim_};
        out = preview_patches(output_.preview(s, p, k));
    }
    if (counts) *counts = k;
    return out;
}

void Solver::preview_moves(const std::map<int, std::array<double, 16>>& moves, FinalGather::Preview& p,
                           std::vector<std::pair<int, Rigid>>& placed) const {
    const size_t no = scene_.objects().size();
    p.moved.assign(no, 0);
    p.carry.assign(no, Rigid{});
    for (const auto& [object, m] : moves) {
        check_live(object, "preview");  // topology.cpp
        const std::vector<Rigid>& poses = edits_.poses();  // an object added since has none yet
        if (size_t(object) >= poses.size() || h_.object_node[size_t(object)] < 0) continue;
        const Rigid to = pose_of(object, m.data());
        const Rigid& from = poses[size_t(object)];
        if (to == from) continue;  // where the solution has it
        const Rigid& c = p.carry[size_t(object)] = to.relative_to(from);
        const Aabb was = h_.object_box(object);
        Aabb now;
        for (int k = 0; k < 8; ++k)
            now.grow(c.point({(k & 1) ? was.hi.x : was.lo.x, (k & 2) ? was.hi.y : was.lo.y, (k & 4) ? was.hi.z : was.lo.z}));
        p.clips.push_back(was);
        p.clips.push_back(now);
        p.moved[size_t(object)] = 1;
        placed.emplace_back(object, to);
    }
    for (Aabb& c : p.clips) {  // ray ends are lifted off surfaces: a hair of margin (as update())
        c.lo -= Vec3{1e-5, 1e-5, 1e-5};
        c.hi += Vec3{1e-5, 1e-5, 1e-5};
    }
    for (size_t k = 1; k < p.clips.size(); k += 2) p.now.push_back(p.clips[k]);
}

std::vector<Solver::PlacedPolygon> Solver::placed_polygons(const FinalGather::Preview& p) const {
    // As DirectLight::find_contacts: coplanar within 1e-7 of the scene, facing the other way, the point inside.
    std::vector<PlacedPolygon> polys;
    const double tol = 1e-7 * h_.scene_diag;
    const size_t no = scene_.objects().size();
    for (const Primitive& pr : h_.prims) {
        if (pr.object < 0 || size_t(pr.object) >= no || !p.moved[size_t(pr.object)]) continue;
        for (int side : {pr.front, pr.back}) {
            if (side < 0) continue;
            const Node& root = h_.nodes[size_t(h_.surfaces[size_t(side)].root)];
            if (root.dead) continue;
            PlacedPolygon q;
            q.poly = root.poly;
            const Rigid& c = p.carry[size_t(pr.object)];
            for (int j = 0; j < q.poly.n; ++j) q.poly.v[size_t(j)] = c.point(root.poly.v[size_t(j)]);
            q.normal = c.dir(root.normal);
            for (int j = 0; j < q.poly.n; ++j) q.box.grow(q.poly.v[size_t(j)]);
            q.box.lo -= Vec3{tol, tol, tol};
            q.box.hi += Vec3{tol, tol, tol};
            polys.push_back(q);
        }
    }
    return polys;
}

std::vector<CornerPatch> Solver::preview_patches(const std::vector<Rgb>& d) const {
    // Only the corners whose light changed: the caller shows the last bake's colours elsewhere.
    std::vector<CornerPatch> out;
    for (size_t o = 0; o < scene_.objects().size(); ++o) {
        const ObjectDesc& od = scene_.objects()[o];
        // A textured surface reflects with each corner's own reflectance (corner_radiance).
        const bool textured = !od.corner_reflectance.empty() || !od.corner_emission.empty();
        CornerPatch patch;
        patch.object = int(o);
        for (size_t f = 0; f < od.polygon_count(); ++f)
            for (int j = 0; j < od.loop_totals[f]; ++j) {
                const size_t c = size_t(od.loop_starts[f]) + size_t(j);
                const int pi = output_.corner_point(int(o), c);
                if (pi < 0) continue;
                const Rgb& dE = d[size_t(pi)];
                if (dE.r == 0 && dE.g == 0 && dE.b == 0) continue;
                Rgb v;
                if (!output_.corner_value(h_, int(o), c, textured, dE, v)) continue;
                if (textured) {
                    const Rgb rho = od.corner_reflectance.empty() ? od.reflectance[f] : od.corner_reflectance[c];
                    const Rgb e = od.corner_emission.empty() ? od.emission[f] : od.corner_emission[c];
                    v = e + rho * v;
                }
                // Stale bounced light plus fresh direct can undershoot where a shadow is cast.
                patch.corners.push_back(int32_t(c));
                patch.values.push_back(std::max(0.f, float(v.r)));
                patch.values.push_back(std::max(0.f, float(v.g)));
                patch.values.push_back(std::max(0.f, float(v.b)));
            }
        if (!patch.corners.empty()) out.push_back(std::move(patch));
    }
    return out;
}

}  // namespace radiosity
