// AdjustSystem (paper 3.3): after objects moved rigidly, were added or were removed, brings the
// kept links up to date with the geometry. Links inside a moved object turn with it, the changed
// clusters' links go and are made anew, the environment's links whose rays may pass through a
// changed box are evaluated again (replayed rays), and enclosures are decided again where escape
// rays meet a changed box. It owns nothing: the hierarchy, links, enclosure table, settings and
// stats are the solver's, handed in a Context for one update with the Change it works from, and
// with the solver's first-bounce judging and phase timer as callbacks.
#pragma once
#include <functional>
#include <map>
#include <vector>

#include "radiosity/enclosure.h"
#include "radiosity/hierarchy.h"
#include "radiosity/link_store.h"
#include "radiosity/refinement.h"
#include "radiosity/rigid.h"
#include "radiosity/settings.h"
#include "radiosity/stats.h"
#include "radiosity/vec.h"

namespace radiosity {

class AdjustSystem {
public:
    using Candidate = Refinement::Candidate;
    // Runs `judge` with the leaves marked in `only` at the lamps' first bounce, the rest as
    // solved (Solver::at_first_bounce).
    using AtFirstBounce = std::function<void(const std::function<void()>& judge, const std::vector<char>* only)>;

    // What an update changed in the geometry (the solver's update for moves, Topology::apply for
    // additions and removals); the adjustment works from it alone.
    struct Change {
        std::vector<Aabb> clips;               // old and new boxes of every changed object
        std::vector<char> inX;                 // per node: its geometry changed (its links are remade)
        std::vector<char> moved;               // per object: moved rigidly (links inside it only turn)
        std::vector<std::vector<int>> chains;  // root-first cluster paths, relinked against their siblings
        std::vector<Candidate> seeds;          // links to make besides (an added object's own links)
        std::vector<Aabb> now;                 // new boxes of the moved objects (exact, no margin)
        std::map<int, Rigid> moves;            // the moves applied: object -> its new placement
    };

    // What one adjustment reads and changes, held by the solver: links are turned, killed,
    // re-evaluated and made, nodes' enclosure answers decided again, the stats counted.
    struct Context {
        Hierarchy& h;
        LinkStore& links;
        Enclosure& enclosure;  // the answers it decides again (Gathering::enclosure)
        const Settings& settings;
        Stats& stats;
        const Change& change;
        // How links are evaluated, made and refined: the solver's refinement with the threshold
        // state of now (Solver::refinement_context).
        Refinement::Context refining;
        AtFirstBounce at_first_bounce;
        // Ends a timed phase of the update (Solver::lap).
        std::function<void(const char* phase)> lap;
    };

    explicit AdjustSystem(Context c) : c_(std::move(c)) {}

    // Marks the moved objects' nodes and the clusters above them in ch.inX (their geometry
    // changed) and adds their root-first chains to ch.chains.
    static void mark_moved(const Hierarchy& h, Change& ch);
    // Runs `judge` with what a move buried at first-bounce radiance, the rest as solved: the
    // leaves of objects that did not move (`moved`, per object) lying inside a moved object's
    // new box (`now`), such as the floor a box now stands on. Their radiance is the one solved
    // before the move, when they were open, which no judgement made for the new placement may
    // take for light (Solver::update_resolve says why). Without such leaves it just runs it.
    static void judge_where_buried(const Hierarchy& h, const std::vector<Aabb>& now, const std::vector<char>& moved,
                                   const AtFirstBounce& at_first_bounce, const std::function<void()>& judge);

    // The adjustment: classifies every live link against the change (turned, remade, pruned by
    // outcodes and the shaft test, re-evaluated with replayed rays), links the changed clusters
    // anew and re-decides the enclosure of leaves whose escape rays meet a changed box. Returns
    // the history links whose view changed (ascending ids), to be asked whether they may
    // coarsen back (Refinement::recheck_history).
    std::vector<int> run();

private:
    // run()'s phases, in order. Every live link against the change; returns the env-env links
    // that may have changed.
    std::vector<int> classify_links();
    // Of `recompute`, keeps the links with a ray that may pass through a changed box.
    void keep_links_rays_meet(std::vector<int>& recompute);
    // Re-evaluates gathered and occluded links (history ones are left stale); a changed one is
    // judged again and its history asked whether it may coarsen back (3.4), into `recheck`.
    void recompute_links(std::vector<int>& recompute, std::vector<int>& recheck);
    // Links the changed clusters anew: env-obj pairs down the chains, added objects' seeds.
    void link_changed();
    // The enclosure deciders ask again, casting only escape rays through a changed box.
    void redecide_enclosures();
    // judge_where_buried's leaves (per node).
    static std::vector<char> buried_leaves(const Hierarchy& h, const std::vector<Aabb>& now,
                                           const std::vector<char>& moved);

    Context c_;
};

}  // namespace radiosity
