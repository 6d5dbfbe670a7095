// The live drag's step as the solver takes it (Solver::preview): the dragged objects placed
// (LiveDrag, which holds them there until anything else reads the solution), what the step
// knows of them (carries, moved boxes, which faces they cover now), FinalGather's preview of
// the direct light at the new places (preview.cpp), and its changes as corner colours.
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "radiosity/parallel.h"
#include "radiosity/solver.h"

namespace radiosity {

namespace {

// A dragged object's polygon at its new place, both sides (the preview's cover test).
struct PlacedPolygon {
    Poly poly;
    Vec3 normal;
    Aabb box;
};

// The dragged objects' polygons where the preview places them, carried from where the solution
// has them (`saved`: their geometry as solved, and their primitives).
std::vector<PlacedPolygon> placed_polygons(const Hierarchy& h, const FinalGather::Preview& p, const LiveDrag& saved,
                                           int threads) {
    // As DirectLight::find_contacts: coplanar within 1e-7 of the scene, facing the other way, the point inside.
    const double tol = 1e-7 * h.scene_diag;
    std::vector<int> all;
    for (const std::vector<int>& own : saved.prims()) all.insert(all.end(), own.begin(), own.end());
    // Two slots per primitive (front, back), filled in parallel, then the empty ones dropped.
    std::vector<PlacedPolygon> slots(2 * all.size());
    std::vector<char> used(2 * all.size(), 0);
    parallel_for(all.size(), threads, [&](size_t k) {
        const Primitive& pr = h.prims[size_t(all[k])];
        for (int b = 0; b < 2; ++b) {
            const int side = b == 0 ? pr.front : pr.back;
            if (side < 0) continue;
            const int root = h.surfaces[size_t(side)].root;
            if (h.nodes[size_t(root)].dead) continue;
            PlacedPolygon& q = slots[2 * k + size_t(b)];
            const Poly& was = saved.poly(root);
            q.poly = was;
            const Rigid& c = p.carry[size_t(pr.object)];
            for (int j = 0; j < q.poly.n; ++j) q.poly.v[size_t(j)] = c.point(was.v[size_t(j)]);
            q.normal = c.dir(saved.normal(root));
            for (int j = 0; j < q.poly.n; ++j) q.box.grow(q.poly.v[size_t(j)]);
            q.box = q.box.grown(tol);
            used[2 * k + size_t(b)] = 1;
        }
    }, 256);
    std::vector<PlacedPolygon> polys;
    polys.reserve(slots.size());
    for (size_t k = 0; k < slots.size(); ++k)
        if (used[k]) polys.push_back(slots[k]);
    return polys;
}

// The corners whose light a preview changes (by object and corner), with their values.
std::vector<CornerPatch> preview_patches(const SceneDesc& scene, const std::vector<FinalGather::CornerChange>& changes) {
    // Only the corners whose light changed: the caller shows the last bake's colours elsewhere.
    std::vector<CornerPatch> out;
    for (size_t k = 0; k < changes.size();) {
        const int o = changes[k].object;
        const ObjectDesc& od = scene.objects()[size_t(o)];
        // A textured surface reflects with each corner's own reflectance (corner_radiance).
        const bool textured = od.textured();
        // (Per corner, its polygon: where one of the two is per polygon.)
        const std::vector<int> polygon = textured && (od.corner_reflectance.empty() || od.corner_emission.empty())
                                             ? od.corner_polygons()
                                             : std::vector<int>{};
        CornerPatch patch;
        patch.object = o;
        for (; k < changes.size() && changes[k].object == o; ++k) {
            const size_t c = size_t(changes[k].corner);
            const size_t f = polygon.empty() ? 0 : size_t(polygon[c]);
            const Rgb v = textured ? od.corner_shading(f, c, changes[k].irradiance) : changes[k].radiance;
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

// What a step knows of the objects it places (`placed`, in `saved`'s order; `poses`: where
// the solution has every object): per object whether it moved and its carry from the
// solution's placement, and the moved boxes, old and new (the new carried from the old).
void step_moves(const std::vector<std::pair<int, Rigid>>& placed, const std::vector<Rigid>& poses,
                const LiveDrag& saved, size_t objects, FinalGather::Preview& p) {
    p.moved.assign(objects, 0);
    p.carry.assign(objects, Rigid{});
    for (size_t j = 0; j < placed.size(); ++j) {
        const auto& [object, to] = placed[j];
        const Rigid& c = p.carry[size_t(object)] = to.relative_to(poses[size_t(object)]);
        const Aabb& was = saved.box(j);
        Aabb now;
        for (int k = 0; k < 8; ++k)
            now.grow(c.point({(k & 1) ? was.hi.x : was.lo.x, (k & 2) ? was.hi.y : was.lo.y, (k & 4) ? was.hi.z : was.lo.z}));
        p.clips.push_back(was);
        p.clips.push_back(now);
        p.moved[size_t(object)] = 1;
    }
    for (Aabb& c : p.clips) c = c.grown(1e-5);  // ray ends are lifted off surfaces: a hair of margin (as update())
    for (size_t k = 1; k < p.clips.size(); k += 2) p.now.push_back(p.clips[k]);
}

// The step's cover tests (FinalGather::Preview::covered, lifted): DirectLight::contact's test,
// with the moved objects where they are now (`polys`, which must outlive p's use of them).
void set_cover_tests(const Hierarchy& h, const DirectLight& direct, const std::vector<PlacedPolygon>& polys,
                     FinalGather::Preview& p) {
    const double tol = 1e-7 * h.scene_diag;
    const double inside_tol = 1e-9 * h.scene_diag;
    const std::vector<std::vector<int>>& contacts = direct.contacts();
    const std::vector<char>& moved = p.moved;
    p.covered = [&h, &contacts, &moved, &polys, tol, inside_tol](int surface, const Vec3& x, const Vec3& n) {
        if (surface >= 0 && size_t(surface) < contacts.size())
            for (int t : contacts[size_t(surface)]) {
                const Node& m = h.nodes[size_t(h.surfaces[size_t(t)].root)];
                if (m.object >= 0 && moved[size_t(m.object)]) continue;  // where it was
                if (within_edges(m.poly, m.normal, x, inside_tol)) return true;
            }
        for (const PlacedPolygon& q : polys) {
            if (!q.box.contains(x) || dot(q.normal, n) > -1 + 1e-6) continue;
            if (std::fabs(dot(x - q.poly.v[0], q.normal)) > tol) continue;
            if (within_edges(q.poly, q.normal, x, inside_tol)) return true;
        }
        return false;
    };
    // (Slid along what it stood on, a face stays in that plane: still covered there, as in the
    // bake. The polygons under its new place are not its contacts; finding them would be a
    // search a step.)
    p.lifted = [&h, &contacts, &moved, tol](int surface, const Vec3& x) {
        if (surface < 0 || size_t(surface) >= contacts.size()) return false;
        bool touched = false;
        for (int t : contacts[size_t(surface)]) {
            const Node& m = h.nodes[size_t(h.surfaces[size_t(t)].root)];
            if (m.object >= 0 && moved[size_t(m.object)]) continue;  // moves with it
            if (std::fabs(dot(x - m.poly.v[0], m.normal)) <= tol) return false;
            touched = true;
        }
        return touched;
    };
}

// The clusters holding any of `objects` (their sampling of surfaces changes with them), ascending.
std::vector<int> clusters_holding(const Hierarchy& h, const std::vector<int>& objects) {
    std::vector<int> out;
    for (int o : objects) {
        const std::vector<int> up = h.clusters_above(o);
        out.insert(out.end(), up.begin(), up.end());
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

}  // namespace

std::vector<CornerPatch> Solver::preview(const std::map<int, std::array<double, 16>>& moves,
                                         FinalGather::PreviewCounts* counts, int64_t work) {
    if (!solved()) throw std::logic_error("preview: solve the scene first");
    if (settings_.gather_rays <= 0 || !output_.traced())
        throw std::logic_error("preview: needs the final gather's trace (gather_rays > 0)");
    const std::vector<std::pair<int, Rigid>> placed = preview_placements(moves);
    std::vector<int> objects;
    for (const auto& op : placed) objects.push_back(op.first);
    // A step that places the objects the last step placed goes on from there; any other puts
    // them back first.
    if (drag_.holds() && drag_.objects() != objects) settle_preview();
    if (counts) *counts = FinalGather::PreviewCounts{};
    if (placed.empty()) return {};
    if (!drag_.holds()) {
        std::vector<std::vector<int>> prims;
        std::vector<Rigid> poses;
        for (int o : objects) {
            prims.push_back(topology_.own_prims(o));
            poses.push_back(edits_.poses()[size_t(o)]);
        }
        drag_.save(h_, objects, std::move(prims), std::move(poses), settings_.threads);
    }
    FinalGather::Preview p;
    step_moves(placed, edits_.poses(), drag_, scene_.objects().size(), p);
    p.work = work < 0 ? settings_.preview_work : work;
    const std::vector<PlacedPolygon> polys = placed_polygons(h_, p, drag_, settings_.threads);
    set_cover_tests(h_, direct_light_, polys, p);
    p.moved_nodes = clusters_holding(h_, objects);
    // The objects stay placed after the step (Embree's and the hierarchy's placements) until
    // settle_preview; a failure on the way puts them back at once.
    drag_.place(h_, *vis_, placed, settings_.threads);
    FinalGather::PreviewCounts k;
    std::vector<CornerPatch> out;
    try {
        const FinalGather::Solution s{scene_, h_, *vis_, links_, gathering_.enclosure(),
                                      [this](int surface, const Vec3& q) { return direct_light_.contact(h_, surface, q); },
                                      &topology_.tri_prim()};
        out = preview_patches(scene_, output_.preview(s, p, k));
    } catch (...) {
        settle_preview();
        throw;
    }
    if (counts) *counts = k;
    return out;
}

void Solver::settle_preview() const { drag_.settle(); }

std::vector<std::pair<int, Rigid>> Solver::preview_placements(const std::map<int, std::array<double, 16>>& moves) const {
    std::vector<std::pair<int, Rigid>> placed;
    for (const auto& [object, m] : moves) {
        topology_.check_live(scene_, object, "preview");
        const std::vector<Rigid>& poses = edits_.poses();  // an object added since has none yet
        if (size_t(object) >= poses.size() || h_.object_node[size_t(object)] < 0) continue;
        const Rigid to = pose_of(object, m);
        if (to == poses[size_t(object)]) continue;  // where the solution has it
        placed.emplace_back(object, to);
    }
    return placed;
}

}  // namespace radiosity
