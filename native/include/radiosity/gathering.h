// Gathering: solves the linked system by iteration (paper 2). Jacobi sweeps gather through the
// links, push irradiance down the hierarchy, reflect it at the leaves and pull radiance back up;
// they run on a gather plan (gather_plan.h) it owns, made from the leaf elements it lists. It
// also owns the enclosure table (enclosure.h) and sets each leaf's closure factors there, which
// the sweeps apply; whether a leaf is enclosed the table decides with its escape rays. The
// hierarchy, links, direct light and stats stay the solver's, handed in at each call; the
// solver says when they changed.
#pragma once
#include <functional>
#include <vector>

#include "radiosity/direct_light.h"
#include "radiosity/enclosure.h"
#include "radiosity/gather_plan.h"
#include "radiosity/hierarchy.h"
#include "radiosity/link_store.h"
#include "radiosity/settings.h"
#include "radiosity/stats.h"

namespace radiosity {

class Gathering {
public:
    // What the sweeps read and write, held by the solver for one call: the nodes' radiances and
    // the links' values are written back, the direct light read, the sweeps and plans counted.
    struct Context {
        Hierarchy& h;
        LinkStore& links;
        const DirectLight& direct_light;
        const Settings& settings;
        Stats& stats;
    };

    // The leaf elements listed anew, the enclosure table fitted to the nodes and the plan
    // dropped. The plan is a snapshot of links, trees, materials, closure factors and direct
    // light: whatever changes those must call this before the next sweep.
    void collect(const Hierarchy& h);
    // The leaf elements at the last collect(), and those of them that are enclosed.
    const std::vector<int>& leaves() const { return leaves_; }
    std::vector<int> enclosed_leaves() const;
    // Per node: whether it is enclosed, and its closure factors (set_closure). The answers are
    // decided by Enclosure::decide, asked by the closure pass and an update's AdjustSystem; a
    // full solve, which builds the hierarchy anew, clears it.
    const Enclosure& enclosure() const { return enclosure_; }
    Enclosure& enclosure() { return enclosure_; }
    // Heap bytes held: the leaf list, the enclosure table and the plan (GatherPlan::bytes, at
    // `links` stored links and `nodes` nodes).
    double bytes(size_t links, size_t nodes) const;

    // One sweep, its radiances copied back to the nodes at once.
    void sweep(const Context& c);
    // Sweeps until the estimated remaining error, relative to `reference` radiance, is below
    // `tolerance`, or max_iterations ran; the nodes get the radiances after the last one (or
    // when `check_cancel` throws). `check_cancel` is called before each sweep, `progress` after
    // each with the fraction of max_iterations run. Returns the sweeps run.
    int iterate_to(const Context& c, double tolerance, int max_iterations, double reference,
                   const std::function<void()>& check_cancel, const std::function<void(double)>& progress);

    // Each leaf's coupling sums: a unit sweep, every sender at radiance 1 (nodes' radiances and
    // links' values are left as the last sweep made them).
    CouplingSums sum_couplings(const Context& c);
    // Each leaf's closure factors from its coupling sums. An enclosed leaf's couplings are
    // corrected toward a sum of 1; `decide_enclosed(leaf)` is asked first for a leaf whose
    // enclosure is not known yet (from several threads at once, each for its own leaf).
    void set_closure(const Context& c, const CouplingSums& sums, const std::function<void(int)>& decide_enclosed);

    // Clusters' radiance, range and direction bins from their children, over the nodes: for
    // code that sets element radiances outside a sweep (the plan does this in its own arrays).
    static void pull_up_clusters(Hierarchy& h);

private:
    // The plan built if it is stale, and its radiometric part prepared if `radiometry`.
    void ensure_plan(const Context& c, bool radiometry);

    std::vector<int> leaves_;  // leaf elements (collect)
    Enclosure enclosure_;      // per node, fitted by collect
    GatherPlan plan_;          // dropped by collect, built by ensure_plan
};

}  // namespace radiosity
