// Refinement (refinement.h): links made wave by wave and judged by the oracle, its judgements
// carried out with the links' bookkeeping and history, closure-driven splits, and history links
// taken back (3.4).
#include "radiosity/refinement.h"

#include <algorithm>
#include <cmath>

#include "radiosity/parallel.h"
#include "radiosity/transfer.h"

namespace radiosity {

uint64_t LinkEvaluator::seed(int src, int rcv) const {
    return Hierarchy::mix(Hierarchy::mix(settings.seed, h.nodes[src].key), h.nodes[rcv].key);
}

Link LinkEvaluator::evaluate(int src, int rcv) const {
    const uint64_t s = seed(src, rcv);
    const Link l = evaluate_link(h, vis, src, rcv, settings.rays_per_link, s);
    if (l.must_refine && !h.nodes[size_t(rcv)].is_cluster() && !oracle.can_split(src) && !oracle.can_split(rcv))
        return limit_link(h, vis, l, settings.rays_per_link, s);
    return l;
}

Link LinkEvaluator::reevaluate(const Link& l) const {
    if (!replay || l.must_refine) return evaluate(l.src, l.rcv);
    return reevaluate_link(h, vis, l, settings.rays_per_link, seed(l.src, l.rcv), *replay);
}

Oracle Refinement::oracle() const {
    return Oracle(c_.h, c_.settings, c_.direct_light, c_.threshold, c_.stats.element_nodes);
}

LinkEvaluator Refinement::evaluator() const { return {c_.h, c_.vis, c_.settings, oracle(), c_.replay}; }

void Refinement::apply(int id, const Judgement& j, std::vector<Candidate>& next) {
    if (j.side == Side::Keep) return;
    if (j.side == Side::Settle) {
        Link& l = c_.links[id];
        l.K = l.K_unoccluded = j.settled_K;
        l.settled = true;
        ++c_.stats.avoided_by_progressive;
        return;
    }
    // The caps are checked here, where links and elements are made: a whole wave is judged
    // before any of it is applied, so the links it queued count too, and a cap is passed by one
    // split at most. Dead links hold no memory beyond their slot and do not count (counted,
    // they stopped later updates' refinement early).
    if (c_.links.live() + int64_t(next.size()) + 4 > c_.settings.max_links) {
        c_.stats.capped = true;
        return;
    }
    if (c_.over_memory(next.size() + 4, 4)) {
        c_.stats.capped = c_.stats.memory_capped = true;
        return;
    }
    const int split = j.side == Side::Src ? c_.links[id].src : c_.links[id].rcv;
    Node& n = c_.h.nodes[split];
    if (!n.is_cluster() && n.children.empty()) {
        if (c_.stats.element_nodes + 4 > c_.settings.max_elements) {
            c_.stats.capped = true;
            return;
        }
        c_.h.subdivide(split);
        c_.stats.element_nodes += 4;
    }
    const Link l = c_.links[id];
    c_.links.deactivate(c_.h, id);
    ++c_.stats.refined_by_oracle;
    for (int c : c_.h.nodes[split].children) {
        if (j.side == Side::Src) next.push_back({c, l.rcv, id});
        else next.push_back({l.src, c, id});
    }
}

void Refinement::link_from(std::vector<Candidate> wave) {
    while (!wave.empty()) {
        c_.before_wave();
        std::vector<Candidate> eval, next;
        // A cluster's self-link stands for every interaction inside it: it is not evaluated but
        // expanded into links between its children and their own self-links.
        for (const Candidate& c : wave) {
            if (c.src != c.rcv) { eval.push_back(c); continue; }
            const Node& n = c_.h.nodes[c.src];
            if (!n.is_cluster()) continue;  // a planar element does not see itself
            for (int a : n.children) {
                if (c_.h.nodes[a].is_cluster()) next.push_back({a, a, -1});
                for (int b : n.children)
                    if (a != b) eval.push_back({a, b, -1});
            }
        }
        std::vector<Link> made(eval.size());
        const LinkEvaluator e = evaluator();
        parallel_for(eval.size(), c_.settings.threads, [&](size_t i) { made[i] = e.evaluate(eval[i].src, eval[i].rcv); }, 16);
        c_.stats.links_evaluated += int64_t(eval.size());
        std::vector<int> ids;
        for (size_t i = 0; i < made.size(); ++i) {
            Link& l = made[i];
            l.parent = eval[i].parent;
            if (l.transports()) {
                ids.push_back(c_.links.add(c_.h, l));
            } else if (l.K_unoccluded > 0) {
                // Possible but fully occluded: kept aside, not gathered, for a move that opens
                // the view (paper 3.3, created links).
                l.occluded = true;
                l.active = false;
                c_.links.add(c_.h, l);
            }
        }
        std::vector<Judgement> js(ids.size());
        const Oracle o = oracle();
        parallel_for(ids.size(), c_.settings.threads, [&](size_t i) { js[i] = o.judge(c_.links[ids[i]]); }, 16);
        for (size_t i = 0; i < ids.size(); ++i) apply(ids[i], js[i], next);
        wave.swap(next);
    }
}

bool Refinement::refine_active(bool* touched) {
    std::vector<int> active;
    for (size_t i = 0; i < c_.links.size(); ++i)
        if (c_.links[i].active) active.push_back(int(i));
    return refine_links(active, touched);
}

bool Refinement::refine_links(const std::vector<int>& ids, bool* touched) {
    std::vector<int> active;
    for (int id : ids)
        if (c_.links[id].active) active.push_back(id);
    std::vector<Judgement> js(active.size());
    const Oracle o = oracle();
    parallel_for(active.size(), c_.settings.threads, [&](size_t i) { js[i] = o.judge(c_.links[active[i]]); }, 256);
    std::vector<Candidate> next;
    bool changed = false;
    if (touched) *touched = false;
    for (size_t i = 0; i < active.size(); ++i) {
        if (js[i].side == Side::Keep) continue;
        if (js[i].side != Side::Settle) changed = true;
        if (touched) *touched = true;
        apply(active[i], js[i], next);
    }
    link_from(std::move(next));
    return changed;
}

namespace {
// Whether a link split toward its receiver's children can hand them different couplings: some
// of its rays are blocked, or its kernel varies over the receiver. Otherwise each child would
// get the coupling it has, and the split would only cost links (docs/decisions.md, "The
// solution").
bool may_differ_below(const Link& l) { return l.partial || l.blocked || l.dK > 0.1 * l.K; }

bool meets_any_box(const std::vector<Aabb>& boxes, const Aabb& b) {
    for (const Aabb& x : boxes)
        if (x.overlaps(b)) return true;
    return false;
}
}  // namespace

// An enclosed leaf's form factors sum to 1. When they sum far from it, links at its element
// ancestors carry a coupling averaged over a receiver much larger than the leaf, which sees
// differently (a ceiling patch hidden by the lamp right under it, a floor patch under a box).
// The oracle cannot tell, each such link being right for its own receiver, and the closure
// correction would scale the leaf's own good links along. So those links split on the receiver
// side; the children are judged as usual, and the next closure pass looks again.
bool Refinement::split_for_closure(const std::vector<int>& leaves, const std::vector<double>& fsum,
                                   const std::vector<Aabb>& focus, int64_t new_from) {
    const double tol = c_.settings.closure_refine_tolerance;
    if (tol <= 0) return false;
    std::vector<char> queued(c_.links.size(), 0);
    std::vector<int> ids;
    const Oracle o = oracle();
    for (int leaf : leaves) {
        const Node& n = c_.h.nodes[leaf];
        if (std::fabs(fsum[leaf] - 1.0) <= tol) continue;
        const bool far = !focus.empty() && !meets_any_box(focus, n.box);
        // Element ancestors only: a cluster link split on the receiver side relinks a whole
        // object, far more links than one leaf's sum can justify.
        for (int a = n.parent; a >= 0 && !c_.h.nodes[a].is_cluster(); a = c_.h.nodes[a].parent)
            for (int li : c_.h.nodes[a].in_links)
                if (!queued[li] && (!far || int64_t(li) >= new_from) && o.can_split(c_.links[li].rcv) &&
                    may_differ_below(c_.links[li])) {
                    queued[li] = 1;
                    ids.push_back(li);
                }
    }
    if (ids.empty()) return false;
    std::sort(ids.begin(), ids.end());  // the links are made in an order that does not vary
    std::vector<Candidate> next;
    Judgement split;
    split.side = Side::Rcv;
    const int64_t before = c_.stats.refined_by_oracle;
    for (int id : ids) {
        c_.links[id].closure_split = true;
        apply(id, split, next);
    }
    const int64_t made = c_.stats.refined_by_oracle - before;
    c_.stats.refined_by_oracle = before;  // these count as closure splits
    c_.stats.refined_by_closure += made;
    if (made == 0) return false;  // at a cap
    link_from(std::move(next));
    return true;
}

void Refinement::refresh(int id, const Link& f) {
    Link& l = c_.links[id];
    l.K = f.K;
    l.K_unoccluded = f.K_unoccluded;
    l.dK = f.dK;
    l.vis = f.vis;
    l.partial = f.partial;
    l.must_refine = f.must_refine;
    l.outline = f.outline;
    l.blocked = f.blocked;
    l.samples = f.samples;
    l.ray_count = f.ray_count;
    l.ray_blocked = f.ray_blocked;
    l.ray_self = f.ray_self;
    l.settled = false;
    l.stale = false;
}

// A settlement (3.5) holds for the sender's radiance it was judged on; these senders' radiance
// as a full solve judges it grew, so the links are evaluated afresh (the rays a full solve casts)
// and the oracle judges them again as new ones.
void Refinement::reopen_settled(const std::vector<int>& ids) {
    std::vector<Link> fresh(ids.size());
    const LinkEvaluator e = evaluator();
    parallel_for(ids.size(), c_.settings.threads,
                 [&](size_t k) { fresh[k] = e.evaluate(c_.links[ids[k]].src, c_.links[ids[k]].rcv); }, 16);
    for (size_t k = 0; k < ids.size(); ++k) refresh(ids[k], fresh[k]);
}

// A stale history link is judged first without rays, as if nothing stood between its ends. One
// that might come back then is evaluated (only the rays through a moved box are cast) and later
// judged as any other, so nothing comes back on stale values. One the ray-free judgement splits
// keeps its split and stays stale: occlusion can lower what the oracle weighs, so this errs
// toward finer than a full solve, never coarser.
void Refinement::freshen_stale(std::vector<int>& ids, bool first_bounce) {
    std::vector<int> stale;
    for (int id : ids)
        if (c_.links[id].stale && !c_.links[id].dead) stale.push_back(id);
    if (stale.empty()) return;
    const LinkEvaluator e = evaluator();
    std::vector<Link> dry(stale.size());
    parallel_for(stale.size(), c_.settings.threads, [&](size_t k) {
        const Link& l = c_.links[stale[k]];
        dry[k] = evaluate_link_unoccluded(c_.h, l.src, l.rcv, c_.settings.rays_per_link, e.seed(l.src, l.rcv));
    }, 64);
    std::vector<Judgement> first(first_bounce ? stale.size() : 0);
    if (first_bounce)
        c_.at_first_bounce([&] {
            const Oracle o = oracle();
            parallel_for(stale.size(), c_.settings.threads, [&](size_t k) { first[k] = o.judge(dry[k]); }, 256);
        });
    std::vector<char> again(stale.size(), 0);
    parallel_for(stale.size(), c_.settings.threads, [&](size_t k) {
        Judgement use;
        again[k] = acceptable_again(dry[k], first_bounce ? &first[k] : nullptr, use);
    }, 256);
    std::vector<int> eval;
    for (size_t k = 0; k < stale.size(); ++k)
        if (again[k]) eval.push_back(stale[k]);
    std::vector<Link> fresh(eval.size());
    parallel_for(eval.size(), c_.settings.threads, [&](size_t k) { fresh[k] = e.reevaluate(c_.links[eval[k]]); }, 16);
    for (size_t k = 0; k < eval.size(); ++k) refresh(eval[k], fresh[k]);
    c_.stats.history_links_recomputed += int64_t(eval.size());
    size_t kept = 0;
    for (int id : ids)
        if (!c_.links[id].stale) ids[kept++] = id;
    ids.resize(kept);
}

// Acceptable again means what a full solve would decide for the link now. A lit scene's full
// solve judges first on the lamps' first bounce (`first`): a split or a settlement made then
// stands, a link kept then may still settle on the solved radiance. Without lamps its rounds
// judge on radiance still gaining its interreflection, whose early contrast splits links the
// solved radiance would settle: only Keep brings a link back. An emitter that reflects nothing
// sends the same radiance in every round, so a settlement stands for it too (docs/decisions.md,
// "Updates").
bool Refinement::acceptable_again(const Link& l, const Judgement* first, Judgement& use) const {
    const Node& S = c_.h.nodes[l.src];
    const bool fixed_sender = !S.is_cluster() && S.rho.max() <= 0 && S.emission.max() > 0;
    const Judgement j = oracle().judge(l);
    use = j;
    const bool settle_ok = first || fixed_sender;
    if (first && first->side == Side::Settle) use = *first;
    else if (first && first->side != Side::Keep) return false;
    else if (settle_ok ? (j.side != Side::Keep && j.side != Side::Settle) : j.side != Side::Keep) return false;
    return true;
}

bool Refinement::unrefine_if_acceptable(int id, const Judgement* first) {
    if (c_.links[id].stale) {  // judged where things are now (the callers freshen_stale first)
        refresh(id, evaluator().reevaluate(c_.links[id]));
        ++c_.stats.history_links_recomputed;
    }
    Judgement use;
    if (!acceptable_again(c_.links[id], first, use)) return false;
    c_.links.kill_refined(c_.h, id);
    c_.links[id].closure_split = false;
    c_.links.activate(c_.h, id);
    ++c_.stats.history_reactivated;
    std::vector<Candidate> none;
    apply(id, use, none);
    return true;
}

// 3.4: history links whose error is acceptable again become active, coarsest first (a parent
// has a lower id than the links refined from it); the links below them go.
void Refinement::unrefine_pass(const std::vector<char>* senders, bool lit) {
    std::vector<int> cand;
    for (size_t i = 0; i < c_.links.size(); ++i) {
        const Link& l = c_.links[i];
        if (senders && (size_t(l.src) >= senders->size() || !(*senders)[l.src])) continue;
        if (!l.dead && !l.active && !l.occluded && !l.closure_split && l.first_child >= 0) cand.push_back(int(i));
    }
    freshen_stale(cand, lit);
    std::vector<Judgement> first(lit ? cand.size() : 0);
    if (lit)
        c_.at_first_bounce([&] {
            const Oracle o = oracle();
            parallel_for(cand.size(), c_.settings.threads, [&](size_t k) { first[k] = o.judge(c_.links[cand[k]]); }, 256);
        });
    for (size_t k = 0; k < cand.size(); ++k) {
        const int id = cand[k];
        if (c_.links[id].dead || c_.links[id].active) continue;  // an ancestor came back first
        unrefine_if_acceptable(id, lit ? &first[k] : nullptr);
    }
}

void Refinement::recheck_history(std::vector<int>& ids) {
    freshen_stale(ids, false);
    // A closure split is undone too: the move changed what its receiver sees, and the next
    // closure pass splits it again if a leaf below still needs it.
    for (int id : ids)  // ascending: a parent before the links it was refined into
        if (!c_.links[id].dead && !c_.links[id].active && !c_.links[id].occluded) unrefine_if_acceptable(id);
}

}  // namespace radiosity
