// The solver's side of gathering (Gathering, gathering.h): the leaf elements listed and lit
// before the sweeps, the sweeps run with the solve's progress and cancellation, and the
// closure passes that alternate closure factors (with enclosure decided by Enclosure's escape
// rays) with closure-driven splits (refinement.h).
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
    gathering_.iterate_to(gather_context(), tolerance, max_iterations, tolerances_.reference,
                          [this] { check_cancel(); }, [&](double f) { set_progress(p0 + (p1 - p0) * f); });
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
        gathering_.set_closure(gather_context(), sums, [this](int leaf) {
            gathering_.enclosure().decide({h_, *vis_, settings_}, leaf, nullptr);
        });
        lap("closure decide");
        const bool split = settings_.closure_rays > 0 && pass < settings_.closure_refine_passes &&
                           refinement(u).split_for_closure(gathering_.enclosed_leaves(), sums.total, focus, new_from);
        lap("closure split");
        if (!split) return pass < settings_.closure_refine_passes || settings_.closure_rays <= 0;
    }
}

}  // namespace radiosity
