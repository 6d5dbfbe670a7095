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
#include <functional>
#include <limits>
#include <stdexcept>
#include <utility>

#include <tbb/enumerable_thread_specific.h>

#include "final_gather_trace.h"
#include "radiosity/lights.h"
#include "radiosity/parallel.h"
#include "radiosity/solver.h"
#include "radiosity/transfer.h"

namespace radiosity {

namespace {

// Whether a shadow ray of some lamp from x (normal n) may meet one of `clips`: a point or spot
// light's segment hull; the sun's rays toward the sun disk; the sky's, anywhere in front
// (unless `sky` is false: lamps whose shadows are sharp and may fall far from the boxes).
bool lamps_meet(const SceneDesc& scene, const Hierarchy& h, const Vec3& x, const Vec3& n, const std::vector<Aabb>& clips,
                bool sky = true) {
    // Whether some clip's bounding sphere comes within `spread` (plus the distance along it
    // times `slope`) of the segment from x along unit u for length len: a quick, conservative
    // test before the shaft's.
    auto near_axis = [&](const Vec3& u, double len, double spread, double slope) {
        for (const Aabb& c : clips) {
            const Vec3 o = c.center() - x;
            const double R = 0.5 * length(c.hi - c.lo) + 1e-4;
            const double t = std::clamp(dot(o, u), 0.0, len);
            if (length(o - u * t) <= R + spread + t * slope) return true;
        }
        return false;
    };
    for (const LightDesc& d : scene.lights()) {
        if (!(d.intensity.max() > 0)) continue;
        if (!sky && d.type == LightDesc::Type::Sky) continue;
        Aabb lb;
        if (d.type == LightDesc::Type::Point || d.type == LightDesc::Type::Spot) {
            const Vec3 q = h.to_internal(d.position);
            const double r = d.radius / h.unit;
            const double len = length(q - x);
            if (len > 0 && !near_axis((q - x) / len, len, r, 0.0)) continue;
            lb.lo = q - Vec3{r, r, r};
            lb.hi = q + Vec3{r, r, r};
        } else if (d.type == LightDesc::Type::Sun) {
            // Past the scene's far end toward the sun, as wide as the disk is there.
            const double far = 4.0 * h.scene_diag;
            const double slope = std::tan(0.5 * std::min(d.angle, 3.0));
            if (!near_axis(normalize(d.direction) * -1.0, far, 1e-9, slope)) continue;
            const Vec3 q = x - d.direction * far;
            const double r = far * slope + 1e-9;
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

// The hierarchy's geometry that placing objects for a preview rewrites
// (Hierarchy::place_object, not whole): their nodes, the clusters above them, their primitives
// and the surface tables where their surfaces and those clusters are. Saved before a preview
// places them, put back after: placing them again from the rest geometry would not give the
// same bits (children's normals are their parents' when built, recomputed when placed).
class SavedGeometry {
public:
    // `prims`: per object of `objects`, its primitives.
    SavedGeometry(const Hierarchy& h, const std::vector<int>& objects, const std::vector<std::vector<int>>& prims) {
        std::vector<char> seen(h.nodes.size(), 0);
        auto keep = [&](int id) {
            if (id < 0 || seen[size_t(id)]) return;
            seen[size_t(id)] = 1;
            const Node& n = h.nodes[size_t(id)];
            nodes_.push_back({id, n.poly, n.normal, n.center, n.box, n.radius, n.area, n.rho_max, n.W});
            if (n.is_cluster()) {
                summaries_.emplace_back(id, h.facing_summary[size_t(id)]);
                for (int k = h.sampler_first[size_t(id)]; k < h.sampler_first[size_t(id) + 1]; ++k)
                    samplers_.emplace_back(k, h.sampler_children[size_t(k)]);
            }
        };
        for (size_t j = 0; j < objects.size(); ++j) {
            const int o = objects[j];
            for (int id : h.object_nodes(o)) keep(id);
            const int top = h.object_node[size_t(o)];
            for (int a = top >= 0 ? h.nodes[size_t(top)].parent : h.root; a >= 0; a = h.nodes[size_t(a)].parent) keep(a);
            if (top >= 0 && h.nodes[size_t(top)].is_cluster())
                for (int i = h.nodes[size_t(top)].surf_begin; i < h.nodes[size_t(top)].surf_end; ++i)
                    geoms_.emplace_back(i, h.surface_geom[size_t(i)]);
            else
                whole_ = true;
            for (int pi : prims[j]) {
                const Primitive& pr = h.prims[size_t(pi)];
                prims_.emplace_back(size_t(pi), pr.poly);
                for (int side : {pr.front, pr.back})
                    if (side >= 0)
                        for (int id : subtree(h, h.surfaces[size_t(side)].root)) keep(id);
            }
        }
        area_prefix_ = h.area_prefix;
        if (whole_) {  // (an unclustered object: placed whole)
            surface_geom_ = h.surface_geom;
            facing_summary_ = h.facing_summary;
            sampler_children_ = h.sampler_children;
        }
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
        h.area_prefix.swap(area_prefix_);
        if (whole_) {
            h.surface_geom.swap(surface_geom_);
            h.facing_summary.swap(facing_summary_);
            h.sampler_children.swap(sampler_children_);
            return;
        }
        for (auto& [i, g] : geoms_) h.surface_geom[size_t(i)] = g;
        for (auto& [id, f] : summaries_) h.facing_summary[size_t(id)] = std::move(f);
        for (const auto& [k, sc] : samplers_) h.sampler_children[size_t(k)] = sc;
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
    std::vector<std::pair<int, SurfaceGeom>> geoms_;
    std::vector<std::pair<int, Hierarchy::FacingSummary>> summaries_;
    std::vector<std::pair<int, Hierarchy::SamplerChild>> samplers_;
    std::vector<double> area_prefix_;
    bool whole_ = false;
    std::vector<SurfaceGeom> surface_geom_;
    std::vector<Hierarchy::FacingSummary> facing_summary_;
    std::vector<Hierarchy::SamplerChild> sampler_children_;
};

// The lists one thread reuses from point to point in a preview.
struct PreviewScratch {
    std::vector<std::pair<int, float>> fresh, samples;
    std::vector<std::pair<int, bool>> reaching;
    std::vector<std::pair<int, double>> use;
    LampRays lamp_rays;
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

// One preview step's points in three runs: those inside an old or new box and those an
// earlier step showed unlit (a footprint: its light must come back as soon as the object
// leaves; relit at every step whatever the work), the dragged objects' own points (from
// `turn` on, so that steps that stop early take turns among them), and the others: first
// those a point, spot or sun light's shadow rays may carry a box's sharp shadow to (a low
// sun throws it across the room), then the rest (the sky's soft shadow), each by distance to
// the nearest box in rings of a 64th of the scene; within a ring by index. The second run is
// [moved_begin, moved_end). Points of no object are left out.
std::vector<uint32_t> preview_order(const FinalGather::Solution& s, const std::vector<fg::Point>& points,
                                    const FinalGather::Preview& p, const std::vector<char>& unlit, size_t turn,
                                    size_t& moved_begin, size_t& moved_end) {
    const Hierarchy& h = s.h;
    constexpr int kRings = 64;
    constexpr uint8_t kNone = 2 * kRings + 2;
    std::vector<uint8_t> ring(points.size(), kNone);
    const double step = h.scene_diag / kRings;
    parallel_for(points.size(), 0, [&](size_t i) {
        const fg::Point& pt = points[i];
        if (pt.object < 0 || size_t(pt.object) >= p.moved.size()) return;
        if (p.moved[size_t(pt.object)]) {
            ring[i] = 1;
            return;
        }
        double d2 = std::numeric_limits<double>::max();
        for (const Aabb& b : p.clips) {
            const Vec3 q = vmax(b.lo, vmin(pt.x, b.hi));
            d2 = std::min(d2, dot(pt.x - q, pt.x - q));
        }
        if (d2 == 0 || unlit[i]) {
            ring[i] = 0;
            return;
        }
        const bool sharp = !pt.covered && lamps_meet(s.scene, h, pt.x, pt.n, p.clips, false);
        ring[i] = uint8_t((sharp ? 2 : 2 + kRings) + std::min(kRings - 1, int(std::sqrt(d2) / step)));
    }, 4096);
    std::vector<size_t> start(size_t(kNone) + 1, 0);
    for (uint8_t r : ring) ++start[size_t(r) + 1];
    for (size_t r = 1; r < start.size(); ++r) start[r] += start[r - 1];
    std::vector<uint32_t> order(start[kNone]);
    std::vector<size_t> at(start.begin(), start.end() - 1);
    for (size_t i = 0; i < points.size(); ++i)
        if (ring[i] < kNone) order[at[ring[i]]++] = uint32_t(i);
    moved_begin = start[1];
    moved_end = start[2];
    const size_t moved = start[2] - start[1];
    if (moved > 0)
        std::rotate(order.begin() + long(start[1]), order.begin() + long(start[1] + turn % moved),
                    order.begin() + long(start[2]));
    return order;
}

// Per node: it emits, or holds an emitting element below it.
std::vector<char> emitting_senders(const Hierarchy& h) {
    std::vector<char> emits(h.nodes.size(), 0);
    for (size_t i = 0; i < h.nodes.size(); ++i) {
        const Node& m = h.nodes[i];
        if (m.dead || m.is_cluster() || !(m.emission.max() > 0)) continue;
        for (int a = int(i); a >= 0 && !emits[size_t(a)]; a = h.nodes[size_t(a)].parent) emits[size_t(a)] = 1;
    }
    return emits;
}

// One preview step: each point's change of irradiance / pi at the new placements (d), whether
// the dragged object covers it now (unlit), and what the step re-traced and cost (work:
// shadow rays streamed from records, each one cast counting 5).
class PreviewStep {
public:
    PreviewStep(const FinalGather::Solution& s, const FinalGather::Preview& p, const FinalGather::Config& config,
                const std::vector<fg::Point>& points, const std::vector<char>& emits,
                std::function<Rgb(const fg::Point&)> bake_value)
        : d(points.size()), unlit(points.size(), 0), s_(s), p_(p), config_(config), points_(points), emits_(emits),
          bake_value_(std::move(bake_value)) {}
    // Point i's change into d[i] (and unlit[i]); adds what it cost to work().
    void relight(size_t i);
    void tally(FinalGather::PreviewCounts& k) const {
        k.points = n_points_;
        k.lamps = n_lamps_;
        k.transfers = n_transfers_;
        k.rays = n_rays_;
        k.uncovered = n_uncovered_;
        k.covered = n_covered_;
    }
    int64_t work() const { return work_; }
    std::vector<Rgb> d;
    std::vector<char> unlit;

private:
    bool footprint(size_t i, const Vec3& x, const Vec3& n, PreviewScratch& sc);
    const FinalGather::Solution& s_;
    const FinalGather::Preview& p_;
    const FinalGather::Config& config_;
    const std::vector<fg::Point>& points_;
    const std::vector<char>& emits_;
    std::function<Rgb(const fg::Point&)> bake_value_;  // what the bake shows at a point
    tbb::enumerable_thread_specific<PreviewScratch> scratch_;
    std::atomic<int64_t> n_points_{0}, n_lamps_{0}, n_transfers_{0}, n_rays_{0}, n_uncovered_{0}, n_covered_{0},
        work_{0};
};

bool inside_any(const std::vector<Aabb>& boxes, const Vec3& x) {
    for (const Aabb& b : boxes)
        if (b.contains(x)) return true;
    return false;
}

// The footprint the dragged object leaves: a point it covered (unlit, no record of what it
// sees) is gathered afresh, roughly; and one it covers now goes unlit. False: neither.
bool PreviewStep::footprint(size_t i, const Vec3& x, const Vec3& n, PreviewScratch& sc) {
    const fg::Point& pt = points_[i];
    const Hierarchy& h = s_.h;
    const int surface = h.nodes[size_t(h.live_element(pt.leaf))].surface;
    if (pt.covered && inside_any(p_.clips, x) && !p_.covered(surface, x, n)) {
        int64_t rays = 0;
        d[i] = fresh_irradiance(s_, config_, pt, sc, rays) - bake_value_(pt);
        n_rays_ += rays;
        work_ += 5 * rays;
        ++n_uncovered_;
        ++n_points_;
        return true;
    }
    if (!pt.covered && inside_any(p_.now, x) && p_.covered(surface, x, n)) {
        d[i] = Rgb{} - bake_value_(pt);
        unlit[i] = 1;
        ++n_covered_;
        ++n_points_;
        return true;
    }
    return false;
}

void PreviewStep::relight(size_t i) {
    const fg::Point& pt = points_[i];
    PreviewScratch& sc = scratch_.local();
    if (pt.object < 0 || size_t(pt.object) >= p_.moved.size()) return;
    const bool moved = p_.moved[size_t(pt.object)] != 0;
    const Vec3 x = moved ? p_.carry[size_t(pt.object)].point(pt.x) : pt.x;
    const Vec3 n = moved ? p_.carry[size_t(pt.object)].dir(pt.n) : pt.n;
    if (!moved && p_.covered && footprint(i, x, n, sc)) return;
    // (A covered point is sealed too under a closed solid: the footprint's rule comes first.)
    if (pt.covered || pt.sealed) {
        d[i] = Rgb{};
        return;
    }
    Rgb dE;
    int64_t rays = 0, streamed = 0;
    bool changed = false;
    if (!s_.scene.lights().empty() && (moved || lamps_meet(s_.scene, s_.h, x, n, p_.clips))) {
        // An unmoved point's shadow rays through neither box keep their recorded outcome; a
        // moved point's are all new, a quarter of them (a preview's approximation, as for a
        // footprint uncovered).
        const int samples = moved ? std::max(4, config_.light_samples / 4) : config_.light_samples;
        const PointLight lamp = direct_light_replay(s_.scene, s_.h, s_.vis, x, n, samples, pt.seed,
                                                    moved ? nullptr : &pt.lamp_rays, &p_.clips, sc.lamp_rays);
        dE += lamp.E - pt.direct;
        rays += lamp.rays;
        streamed += sc.lamp_rays.count;
        ++n_lamps_;
        changed = true;
    }
    const int64_t transfers = add_emitter_changes(s_, p_, config_, pt, x, n, moved, emits_, sc.fresh, dE, rays);
    n_transfers_ += transfers;
    d[i] = dE;
    n_points_ += changed || transfers > 0;
    n_rays_ += rays;
    work_ += streamed + 4 * rays;
}

// A step that stops at `limit` work: the points inside the boxes (order's first run) all,
// then chunks from the dragged objects' points and from the others (nearest first), the side
// that has had less work first, so that the shadow a dragged armchair casts follows it even
// where its own points alone would take all the work. Marks the points relit in `done`;
// returns how many of the dragged points were.
size_t relight_in_order(PreviewStep& step, const std::vector<uint32_t>& order, size_t moved_begin, size_t moved_end,
                        int64_t limit, int threads, std::vector<char>& done, size_t& deferred) {
    // (Chunks of up to 256 points, a sixteenth of a small scene's: the work is checked
    // between chunks.)
    const size_t chunk = std::clamp<size_t>(order.size() / 16, 16, 256);
    auto run = [&](size_t from, size_t to) {
        parallel_for(to - from, threads, [&](size_t j) {
            step.relight(order[from + j]);
            done[order[from + j]] = 1;
        }, 8);
    };
    for (size_t k = 0; k < moved_begin; k += chunk) run(k, std::min(moved_begin, k + chunk));
    size_t mv = moved_begin, env = moved_end;
    int64_t spent[2] = {step.work(), 0};  // by the others (the boxes' insides too), by the dragged points
    while (step.work() < limit && (mv < moved_end || env < order.size())) {
        const bool dragged = mv < moved_end && (env == order.size() || spent[1] <= spent[0]);
        size_t& at = dragged ? mv : env;
        const size_t to = std::min(dragged ? moved_end : order.size(), at + chunk);
        const int64_t before = step.work();
        run(at, to);
        spent[dragged] += step.work() - before;
        at = to;
    }
    deferred = (moved_end - mv) + (order.size() - env);
    return mv - moved_begin;
}

}  // namespace

std::vector<Rgb> FinalGather::preview(const Solution& s, const Preview& p, PreviewCounts& counts) {
    if (!traced()) return {};
    Impl& t = *impl_;
    const std::vector<fg::Point>& points = t.points;
    Impl::PreviewState& shown = t.preview_state;
    if (shown.moved != p.moved || shown.shown.size() != points.size()) {
        shown.moved = p.moved;
        shown.shown.assign(points.size(), Rgb{});
        shown.unlit.assign(points.size(), 0);
        shown.turn = 0;
    }
    // Only emitting senders' transfers are re-traced (a dark sender's light is bounced light,
    // left as solved); which they are is found once per trace.
    if (shown.emits.size() != s.h.nodes.size()) shown.emits = emitting_senders(s.h);
    PreviewStep step(s, p, t.config, points, shown.emits,
                     [&](const fg::Point& pt) { return t.point_value(s.h, pt, true); });
    if (p.work <= 0) {
        parallel_for(points.size(), t.config.threads, [&](size_t i) { step.relight(i); }, 8);
    } else {
        // The rest show what an earlier step of the drag showed.
        size_t moved_begin = 0, moved_end = 0, deferred = 0;
        const std::vector<uint32_t> order =
            preview_order(s, points, p, shown.unlit, shown.turn, moved_begin, moved_end);
        std::vector<char> done(points.size(), 0);
        shown.turn += relight_in_order(step, order, moved_begin, moved_end, p.work, t.config.threads, done, deferred);
        for (size_t i = 0; i < points.size(); ++i) {
            if (done[i]) shown.shown[i] = step.d[i], shown.unlit[i] = step.unlit[i];
            else step.d[i] = shown.shown[i];
        }
        counts.deferred = int64_t(deferred);
    }
    step.tally(counts);
    return std::move(step.d);
}

bool FinalGather::corner_value(const Hierarchy& h, int object, size_t corner, bool irradiance, const Rgb& change,
                               Rgb& out) const {
    const int p = corner_point(object, corner);
    if (p < 0) return false;
    out = impl_->point_value(h, impl_->points[size_t(p)], irradiance, change);
    return true;
}

namespace {

// A dragged object's polygon at its new place, both sides (the preview's cover test).
struct PlacedPolygon {
    Poly poly;
    Vec3 normal;
    Aabb box;
};

// The dragged objects' polygons where the preview places them.
std::vector<PlacedPolygon> placed_polygons(const SceneDesc& scene, const Hierarchy& h, const FinalGather::Preview& p) {
    // As DirectLight::find_contacts: coplanar within 1e-7 of the scene, facing the other way, the point inside.
    std::vector<PlacedPolygon> polys;
    const double tol = 1e-7 * h.scene_diag;
    const size_t no = scene.objects().size();
    for (const Primitive& pr : h.prims) {
        if (pr.object < 0 || size_t(pr.object) >= no || !p.moved[size_t(pr.object)]) continue;
        for (int side : {pr.front, pr.back}) {
            if (side < 0) continue;
            const Node& root = h.nodes[size_t(h.surfaces[size_t(side)].root)];
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

// The corners whose colour the per-point changes `d` alter, and their values.
std::vector<CornerPatch> preview_patches(const SceneDesc& scene, const Hierarchy& h, const FinalGather& output,
                                         const std::vector<Rgb>& d) {
    // Only the corners whose light changed: the caller shows the last bake's colours elsewhere.
    std::vector<CornerPatch> out;
    for (size_t o = 0; o < scene.objects().size(); ++o) {
        const ObjectDesc& od = scene.objects()[o];
        // A textured surface reflects with each corner's own reflectance (corner_radiance).
        const bool textured = !od.corner_reflectance.empty() || !od.corner_emission.empty();
        CornerPatch patch;
        patch.object = int(o);
        for (size_t f = 0; f < od.polygon_count(); ++f)
            for (int j = 0; j < od.loop_totals[f]; ++j) {
                const size_t c = size_t(od.loop_starts[f]) + size_t(j);
                const int pi = output.corner_point(int(o), c);
                if (pi < 0) continue;
                const Rgb& dE = d[size_t(pi)];
                if (dE.r == 0 && dE.g == 0 && dE.b == 0) continue;
                Rgb v;
                if (!output.corner_value(h, int(o), c, textured, dE, v)) continue;
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

}  // namespace

std::vector<CornerPatch> Solver::preview(const std::map<int, std::array<double, 16>>& moves,
                                         FinalGather::PreviewCounts* counts, int64_t work) {
    if (!solved_) throw std::logic_error("preview: solve the scene first");
    if (settings_.gather_rays <= 0 || !output_.traced())
        throw std::logic_error("preview: needs the final gather's trace (gather_rays > 0)");
    FinalGather::Preview p;
    std::vector<std::pair<int, Rigid>> placed;
    preview_moves(moves, p, placed);
    p.work = work < 0 ? settings_.preview_work : work;
    // (DirectLight::contact's test, with the moved objects where they are now.)
    const std::vector<PlacedPolygon> polys = placed_polygons(scene_, h_, p);
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
    // Each dragged object's primitives (its Embree triangles', a quad's two named once).
    std::vector<int> objects;
    std::vector<std::vector<int>> prims;
    for (const auto& op : placed) {
        objects.push_back(op.first);
        std::vector<int>& own = prims.emplace_back();
        for (int pi : tri_prim_[size_t(op.first)])
            if (own.empty() || own.back() != pi) own.push_back(pi);
    }
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
    } restore{this, placed, place, SavedGeometry(h_, objects, prims)};
    for (size_t j = 0; j < placed.size(); ++j) {
        place(placed[j].first, placed[j].second);
        h_.place_object(placed[j].first, placed[j].second, false, &prims[j]);  // (put back by `restore`)
    }
    if (!placed.empty()) vis_->commit();

    FinalGather::PreviewCounts k;
    std::vector<CornerPatch> out;
    if (!placed.empty()) {
        const FinalGather::Solution s{scene_, h_, *vis_, links_,
                                      [this](int surface, const Vec3& q) { return direct_light_.contact(h_, surface, q); }, &tri_prim_};
        out = preview_patches(scene_, h_, output_, output_.preview(s, p, k));
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

}  // namespace radiosity
