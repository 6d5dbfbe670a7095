// The solver's side of gathering (Gathering, gathering.h): the leaf elements listed and lit
// before the sweeps, the sweeps run with the solve's progress and cancellation, the closure
// passes that alternate closure factors with closure-driven splits (refinement.h), and the
// escape rays that decide whether a leaf is enclosed.
#include <utility>

#include "radiosity/solver.h"

namespace radiosity {

void Solver::collect_receivers(const UpdateRun* u) {
    gathering_.collect(h_);
    // The direct light of the leaves lacking it: new ones, and every one after a light changed
    // or objects moved.
    direct_light_.prepare(h_, light_sight(), gathering_.leaves(), edits_.poses(), replay_boxes(u));
}

void Solver::iterate_to(const UpdateRun* u, double tolerance, int max_iterations, double p0, double p1,
                        bool keep_plan) {
    if (!keep_plan) collect_receivers(u);
    gathering_.iterate_to(gather_context(), tolerance, max_iterations, L_ref_, [this] { check_cancel(); },
                          [&](double f) { set_progress(p0 + (p1 - p0) * f); });
}

// The closure correction (Gathering::set_closure) on the links as they stand, then the links
// that an enclosed leaf's sums say are too coarse split (Refinement::split_for_closure), pass after pass until
// none is. A leaf decides with its own escape rays the first time it is a leaf in a closure
// pass; its children inherit the answer (and the decider) when it splits.
bool Solver::compute_closure(const UpdateRun* u) {
    // An update's closure passes split, away from its moved boxes, only the links it made.
    static const std::vector<Aabb> no_focus;
    const std::vector<Aabb>& focus = u ? u->closure_focus : no_focus;
    const int64_t new_from = u ? u->links_before : 0;
    for (int pass = 0;; ++pass) {
        collect_receivers(u);
        const CouplingSums sums = gathering_.sum_couplings(gather_context());
        lap("closure sums");
        gathering_.set_closure(gather_context(), sums, [this](int leaf) { decide_enclosed(leaf, nullptr); });
        lap("closure decide");
        const bool split = settings_.closure_rays > 0 && pass < settings_.closure_refine_passes &&
                           refinement(u).split_for_closure(gathering_.enclosed_leaves(), sums.total, focus, new_from);
        lap("closure split");
        if (!split) return pass < settings_.closure_refine_passes || settings_.closure_rays <= 0;
    }
}

// The escape rays of a node: cosine-distributed from random points of its polygon, lifted
// off it, reaching beyond the scene. Deterministic per node key.
void Solver::escape_rays(const Node& n, std::vector<std::pair<Vec3, Vec3>>& rays) const {
    const double far = 4.0 * h_.scene_diag;
    const double lift = 1e-5 * h_.scene_diag;  // off its own surface; tnear 0 sees neighbours
    Rng rng(Hierarchy::mix(settings_.seed, n.key));
    Vec3 u, v;
    frame(n.normal, u, v);
    rays.clear();
    for (int r = 0; r < settings_.closure_rays; ++r) {
        double r1 = rng.next(), r2 = rng.next();
        Vec3 d = cosine_direction(u, v, n.normal, r1, r2);
        const double s2 = rng.next(), s1 = rng.next();  // named: the order is every compiler's
        Vec3 o = n.poly.sample(s1, s2) + n.normal * lift;
        rays.emplace_back(o, o + d * far);
    }
}

// Decides (or, after a move, re-decides) whether a node's escape rays find open space. With
// `moved_boxes`, the node was decided before and did not move itself: only rays through a
// moved object's old or new box can have changed outcome.
void Solver::decide_enclosed(int id, const std::vector<Aabb>* moved_boxes) {
    Enclosure& e = gathering_.enclosure();
    std::vector<std::pair<Vec3, Vec3>> rays;
    escape_rays(h_.nodes[id], rays);
    auto meets = [&](int r) { return meets_any(*moved_boxes, rays[r].first, rays[r].second); };
    if (moved_boxes && e.enclosed(id) == 1) {
        for (int r = 0; r < int(rays.size()); ++r)
            if (meets(r) && !vis_->occluded(rays[r].first, rays[r].second, 0.0)) {
                e.open(id, r);
                return;
            }
        return;  // every ray still blocked
    }
    const int witness = e.escape_ray(id);
    if (moved_boxes && e.enclosed(id) == 0 && witness >= 0 && !meets(witness)) return;  // witness still clear
    for (int r = 0; r < int(rays.size()); ++r)
        if (!vis_->occluded(rays[r].first, rays[r].second, 0.0)) {
            e.decide(id, r);
            return;
        }
    e.decide(id, -1);
}

}  // namespace radiosity
