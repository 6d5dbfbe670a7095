// Refinement: makes links and refines them with the oracle (oracle.h). It links wave by wave
// from seed pairs down, applies the oracle's judgements (splits into the children's links,
// settlements, 3.5), splits the links an enclosed leaf's closure sums call too coarse, and takes
// history links back where the oracle accepts them again (3.4). It owns nothing: the hierarchy,
// links, visibility, settings, stats and threshold state are the solver's, handed in a Context
// for one step, with the solver's cancellation, memory cap and first-bounce judging as callbacks.
// Also here: LinkEvaluator, how any link is evaluated (its rays seeded by its two ends), which
// the refinement, the update's adjust system and the solver's own re-evaluations all share.
#pragma once
#include <cstdint>
#include <functional>
#include <vector>

#include "radiosity/direct_light.h"
#include "radiosity/hierarchy.h"
#include "radiosity/link.h"
#include "radiosity/link_store.h"
#include "radiosity/oracle.h"
#include "radiosity/settings.h"
#include "radiosity/stats.h"
#include "radiosity/visibility.h"

namespace radiosity {

// How the solver evaluates a link, whoever asks: rays jittered by a seed made of the two ends'
// stable keys, so the same pair gets the same rays whether a full solve or an update links it.
struct LinkEvaluator {
    const Hierarchy& h;
    const Visibility& vis;
    const Settings& settings;
    const Oracle oracle;               // asked only whether an end may split
    const std::vector<Aabb>* replay;   // an update's moved boxes, outside which rays replay (null: none)

    uint64_t seed(int src, int rcv) const;
    // A fresh evaluation. At the resolution limit a link the point model cannot evaluate takes
    // its coupling from point transfers (limit_link) instead of 0.
    Link evaluate(int src, int rcv) const;
    // The same for a kept link whose ends did not move: with `replay`, the rays through no box
    // of it keep their recorded outcome (reevaluate_link); otherwise evaluate().
    Link reevaluate(const Link& l) const;
};

class Refinement {
public:
    // A link to make: src -> rcv, refined from link `parent` (-1: none).
    struct Candidate { int src, rcv, parent; };

    // What one step reads and changes, held by the solver: links and elements are made,
    // split and killed, the stats counted; the threshold state is the one of now.
    struct Context {
        Hierarchy& h;
        LinkStore& links;
        const Visibility& vis;
        const DirectLight& direct_light;
        const Settings& settings;
        Stats& stats;
        Oracle::Threshold threshold;
        const std::vector<Aabb>* replay;  // LinkEvaluator::replay
        // Before each wave of links: throws to cancel; keeps the memory forecast current.
        std::function<void()> before_wave;
        // Whether `more_links` links and `more_nodes` nodes more would pass the memory cap.
        std::function<bool(size_t more_links, size_t more_nodes)> over_memory;
        // Runs `judge` with the nodes at the lamps' first bounce (Solver::at_first_bounce).
        std::function<void(const std::function<void()>& judge)> at_first_bounce;
    };

    explicit Refinement(Context c) : c_(std::move(c)) {}

    // Evaluates the candidates, keeps those that transport (fully occluded ones as history, so a
    // move that opens the view can bring them back), judges them and makes the next wave from
    // their splits, until a wave is empty. A cluster's self-link expands into its children's.
    void link_from(std::vector<Candidate> wave);
    // One round of judgements over the active ones of `ids`, their splits linked; true when any
    // link split (settlements alone do not count). `touched`, if given: whether any link was
    // split or settled (false: the links are as they were).
    bool refine_links(const std::vector<int>& ids, bool* touched = nullptr);
    // refine_links over every active link.
    bool refine_active(bool* touched = nullptr);
    // Splits, on the receiver side, the element links above `leaves` (enclosed ones:
    // Gathering::enclosed_leaves) whose sums of couplings (`fsum`, per node) are off 1; true if
    // any split. Away from the `focus` boxes (none: no focus) only links from `new_from` on split.
    bool split_for_closure(const std::vector<int>& leaves, const std::vector<double>& fsum,
                           const std::vector<Aabb>& focus, int64_t new_from);

    // Takes a fresh evaluation's coupling, visibility and samples into kept link `id`.
    void refresh(int id, const Link& fresh);
    // Settled links (3.5) whose sender's light grew: evaluated afresh and unsettled.
    void reopen_settled(const std::vector<int>& ids);
    // History links, coarsest first, taken back where the oracle accepts them again; only those
    // whose sender is marked in `senders` (all when null). `lit`: the scene has lamps, whose
    // first bounce a full solve judges by first.
    void unrefine_pass(const std::vector<char>* senders, bool lit);
    // History links whose view a move changed (ascending ids): taken back where acceptable.
    void recheck_history(std::vector<int>& ids);
    // How links are evaluated here: on the threshold state, the element count of now and the
    // update's replay boxes.
    LinkEvaluator evaluator() const;

private:
    using Side = Oracle::Side;
    using Judgement = Oracle::Judgement;

    // The oracle on the threshold state and the element count of now.
    Oracle oracle() const;
    // A judgement carried out: a settlement, or link `id` split on the side it names into
    // candidates appended to `next` (nothing at a cap).
    void apply(int id, const Judgement& j, std::vector<Candidate>& next);
    // The stale among `ids` that a judgement without rays would not take back are dropped from
    // `ids` (they stay stale); the others are evaluated. `first_bounce`: judged as in a lit scene.
    void freshen_stale(std::vector<int>& ids, bool first_bounce);
    // Whether a history link would be taken back now, and with which judgement (`use`).
    // `first`: its judgement on the lamps' first bounce, if known.
    bool acceptable_again(const Link& l, const Judgement* first, Judgement& use) const;
    // A history link reactivated (the links below it killed) where acceptable_again; true if so.
    bool unrefine_if_acceptable(int id, const Judgement* first = nullptr);

    Context c_;
};

}  // namespace radiosity
