// Linking and refinement: links made wave by wave from the root cluster down and judged by
// the oracle (oracle.h), its judgements applied (splits, 3.5 settlements) with link bookkeeping
// and history links, and closure-driven refinement.
#include <algorithm>
#include <cmath>

#include "radiosity/parallel.h"
#include "radiosity/solver.h"
#include "radiosity/transfer.h"

namespace radiosity {

// Jitter seeded by the two ends' stable keys: the same pair gets the same rays whether it
// is linked by a full solve or by an incremental update.
uint64_t Solver::link_seed(int src, int rcv) const {
    return Hierarchy::mix(Hierarchy::mix(settings_.seed, h_.nodes[src].key), h_.nodes[rcv].key);
}

Link Solver::evaluate(int src, int rcv) const {
    settle_preview();
    const uint64_t seed = link_seed(src, rcv);
    const Link l = evaluate_link(h_, *vis_, src, rcv, settings_.rays_per_link, seed);
    // At the resolution limit a link the point model cannot evaluate stays as it is: its
    // coupling is then taken from point transfers (limit_link) instead of left at 0.
    const Oracle o = oracle();
    if (l.must_refine && !h_.nodes[size_t(rcv)].is_cluster() && !o.can_split(src) && !o.can_split(rcv))
        return limit_link(h_, *vis_, l, settings_.rays_per_link, seed);
    return l;
}

Link Solver::reevaluate(const Link& l) const {
    // (evaluate puts a drag's placement back; a replay runs only inside update, which did.)
    if (!update_run_ || !update_run_->replaying || l.must_refine) return evaluate(l.src, l.rcv);
    return reevaluate_link(h_, *vis_, l, settings_.rays_per_link, link_seed(l.src, l.rcv), update_run_->replay_clips);
}

void Solver::apply(int id, const Judgement& j, std::vector<Candidate>& next) {
    if (j.side == Side::Keep) return;
    if (j.side == Side::Settle) {
        Link& l = links_[id];
        l.K = l.K_unoccluded = j.settled_K;
        l.settled = true;
        ++stats_.avoided_by_progressive;
        return;
    }
    // The caps are checked here, where links and elements are made, not only when judging
    // (a whole wave is judged before any of it is applied): links counted with the ones this
    // wave has queued, so the cap is exceeded by at most one refinement. Dead links (killed by
    // an update) do not count: they hold no memory beyond their slot, and counting them made
    // later updates stop refining early (an object removed and added back came out 50 % too
    // bright where its cluster links stayed coarse).
    if (links_.live() + int64_t(next.size()) + 4 > settings_.max_links) {
        stats_.capped = true;
        return;
    }
    if (memory_estimate(next.size() + 4, 4) > memory_limit_) {  // with the links this wave queued
        stats_.capped = stats_.memory_capped = true;
        return;
    }
    const int split = j.side == Side::Src ? links_[id].src : links_[id].rcv;
    Node& n = h_.nodes[split];
    if (!n.is_cluster() && n.children.empty()) {
        if (stats_.element_nodes + 4 > settings_.max_elements) {
            stats_.capped = true;
            return;
        }
        h_.subdivide(split);
        stats_.element_nodes += 4;
    }
    const Link l = links_[id];
    links_.deactivate(h_, id);
    ++stats_.refined_by_oracle;
    for (int c : h_.nodes[split].children) {
        if (j.side == Side::Src) next.push_back({c, l.rcv, id});
        else next.push_back({l.src, c, id});
    }
}

namespace {
// The output's forecast is made again once there are this many links, then at each doubling.
constexpr int64_t kForecastLinks = 10000;
}  // namespace

void Solver::link_from(std::vector<Candidate> wave) {
    while (!wave.empty()) {
        check_cancel();
        // The output's forecast follows the links: made again each time they have doubled,
        // and wave by wave near the memory cap (memory.cpp). Once the output is traced (an
        // update), the estimate counts the trace itself: no forecast, which would read every
        // link and corner of the scene.
        if (!output_.traced() &&
            (links_.live() >= std::max<int64_t>(kForecastLinks, 2 * output_forecast_links_) ||
             memory_estimate() > 0.5 * memory_limit_))
            forecast_output();
        std::vector<Candidate> eval, next;
        // A self-link of a cluster stands for all interactions inside it: expand it into
        // links between its children (and their own self-links) without evaluating it.
        for (const Candidate& c : wave) {
            if (c.src != c.rcv) { eval.push_back(c); continue; }
            const Node& n = h_.nodes[c.src];
            if (!n.is_cluster()) continue;  // a planar element does not see itself
            for (int a : n.children) {
                if (h_.nodes[a].is_cluster()) next.push_back({a, a, -1});
                for (int b : n.children)
                    if (a != b) eval.push_back({a, b, -1});
            }
        }
        std::vector<Link> made(eval.size());
        parallel_for(eval.size(), settings_.threads, [&](size_t i) { made[i] = evaluate(eval[i].src, eval[i].rcv); }, 16);
        stats_.links_evaluated += int64_t(eval.size());
        std::vector<int> ids;
        for (size_t i = 0; i < made.size(); ++i) {
            Link& l = made[i];
            if (!l.transports()) {
                // Geometrically possible but fully occluded: kept aside (not gathered) so that
                // a move that opens the view can bring it back (paper 3.3, created links).
                if (l.K_unoccluded > 0) {
                    l.parent = eval[i].parent;
                    l.occluded = true;
                    l.active = false;
                    links_.add(h_, l);
                }
                continue;
            }
            l.parent = eval[i].parent;
            ids.push_back(links_.add(h_, l));
        }
        std::vector<Judgement> js(ids.size());
        const Oracle o = oracle();
        parallel_for(ids.size(), settings_.threads, [&](size_t i) { js[i] = o.judge(links_[ids[i]]); }, 16);
        for (size_t i = 0; i < ids.size(); ++i) apply(ids[i], js[i], next);
        wave.swap(next);
    }
}

bool Solver::refine_round() {
    const bool lights_split = light_refine();  // solver_lights.cpp: where direct light varies
    std::vector<int> active;
    for (size_t i = 0; i < links_.size(); ++i)
        if (links_[i].active) active.push_back(int(i));
    const bool links_split = refine_links(active);
    return links_split || lights_split;
}

bool Solver::refine_links(const std::vector<int>& ids) {
    std::vector<int> active;
    for (int id : ids)
        if (links_[id].active) active.push_back(id);
    std::vector<Judgement> js(active.size());
    const Oracle o = oracle();
    parallel_for(active.size(), settings_.threads, [&](size_t i) { js[i] = o.judge(links_[active[i]]); }, 256);
    std::vector<Candidate> next;
    bool changed = false;
    for (size_t i = 0; i < active.size(); ++i) {
        if (js[i].side == Side::Keep) continue;
        if (js[i].side != Side::Settle) changed = true;
        apply(active[i], js[i], next);
    }
    link_from(std::move(next));
    return changed;
}

// Whether splitting a link toward a receiver's children can change what they get: its
// visibility is uncertain (some rays blocked) or its kernel varies over the receiver. A clear
// link with a flat kernel hands every child the coupling it has; splitting it only costs
// links (docs/decisions.md, "The solution").
static bool may_differ_below(const Link& l) { return l.partial || l.blocked || l.dK > 0.1 * l.K; }

// Closure-driven refinement. The form factors of an enclosed leaf must sum to 1. A sum far
// off 1 means that links at its ancestors carry a coupling averaged over a receiver much
// larger than the leaf, whose own view differs: a lamp right under a ceiling hides most of
// the room from the ceiling patch above it, a box resting on a floor hides it from the floor
// under it, yet the big ancestor sees it all (sum ~2). The oracle cannot tell -- each such
// link is accurate for its own receiver -- and the closure correction would scale the leaf's
// own, correct links down with the rest. So those ancestor links are split on the receiver
// side; the children are judged as usual, and the next pass looks again.
bool Solver::closure_refine(const std::vector<double>& fsum) {
    const double tol = settings_.closure_refine_tolerance;
    if (tol <= 0) return false;
    std::vector<char> queued(links_.size(), 0);
    std::vector<int> ids;
    const Oracle o = oracle();
    for (int leaf : gathering_.leaves()) {
        const Node& n = h_.nodes[leaf];
        if (n.enclosed != 1 || std::fabs(fsum[leaf] - 1.0) <= tol) continue;
        // During an update, a leaf away from the moved boxes has only the new links split.
        bool far = update_run_ && !update_run_->closure_focus.empty();
        if (far)
            for (const Aabb& b : update_run_->closure_focus)
                if (b.overlaps(n.box)) { far = false; break; }
        // Element ancestors only: splitting a cluster link on the receiver side re-links a
        // whole object (overlapping sub-clusters go down to element pairs), millions of links
        // in a furnished room for what one leaf's sum says.
        for (int a = n.parent; a >= 0 && !h_.nodes[a].is_cluster(); a = h_.nodes[a].parent)
            for (int li : h_.nodes[a].in_links)
                if (!queued[li] && (!far || int64_t(li) >= update_run_->links_before) &&
                    o.can_split(links_[li].rcv) && may_differ_below(links_[li])) {
                    queued[li] = 1;
                    ids.push_back(li);
                }
    }
    if (ids.empty()) return false;
    std::sort(ids.begin(), ids.end());  // deterministic order of the links made
    std::vector<Candidate> next;
    Judgement split;
    split.side = Side::Rcv;
    const int64_t before = stats_.refined_by_oracle;
    for (int id : ids) {
        links_[id].closure_split = true;
        apply(id, split, next);
    }
    const int64_t made = stats_.refined_by_oracle - before;
    stats_.refined_by_oracle = before;  // counted as closure splits, not oracle ones
    stats_.refined_by_closure += made;
    if (made == 0) return false;  // at a cap
    link_from(std::move(next));
    return true;
}

}  // namespace radiosity
