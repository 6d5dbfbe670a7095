// AdjustSystem (adjust_system.h): the kept links brought up to date after a change of geometry,
// phase by phase: classified, probed, re-evaluated, relinked, and enclosures decided again.
#include "radiosity/adjust_system.h"

#include <algorithm>
#include <set>

#include "radiosity/parallel.h"

namespace radiosity {

namespace {
// 3-D Cohen-Sutherland outcode of a box against a clipping volume, generalised from points
// to boxes: a bit is set only when the whole box lies beyond that plane. Two boxes whose
// codes share a bit lie beyond the same plane, and so does every segment between them.
unsigned outcode(const Aabb& b, const Aabb& clip) {
    unsigned c = 0;
    for (int a = 0; a < 3; ++a) {
        if (b.hi[a] < clip.lo[a]) c |= 1u << (2 * a);
        if (b.lo[a] > clip.hi[a]) c |= 2u << (2 * a);
    }
    return c;
}
}  // namespace

void AdjustSystem::mark_moved(const Hierarchy& h, Change& ch) {
    for (const auto& move : ch.moves) {
        const int obj = move.first;
        for (int id : h.object_nodes(obj)) ch.inX[id] = 1;
        std::vector<int> chain;
        for (int a = h.object_node[obj]; a >= 0; a = h.nodes[a].parent) chain.push_back(a);
        for (int a : chain)
            if (a != h.root) ch.inX[a] = 1;
        std::reverse(chain.begin(), chain.end());  // root first
        ch.chains.push_back(chain);
    }
}

std::vector<char> AdjustSystem::buried_leaves(const Hierarchy& h, const std::vector<Aabb>& now,
                                              const std::vector<char>& moved) {
    std::vector<char> b(h.nodes.size(), 0);
    std::vector<Aabb> boxes;  // `now` with a margin: a floor under a box lies in the box's bottom plane
    for (const Aabb& c : now) boxes.push_back(c.grown(1e-6 * h.scene_diag));
    for (size_t i = 0; i < h.nodes.size(); ++i) {
        const Node& n = h.nodes[i];
        if (n.dead || n.is_cluster() || !n.children.empty() || (n.object >= 0 && moved[size_t(n.object)])) continue;
        for (const Aabb& c : boxes) {
            bool in = true;
            for (int a = 0; a < 3 && in; ++a) in = n.box.lo[a] >= c.lo[a] && n.box.hi[a] <= c.hi[a];
            if (in) {
                b[i] = 1;
                break;
            }
        }
    }
    return b;
}

void AdjustSystem::judge_where_buried(const Hierarchy& h, const std::vector<Aabb>& now, const std::vector<char>& moved,
                                      const AtFirstBounce& at_first_bounce, const std::function<void()>& judge) {
    const std::vector<char> buried = now.empty() ? std::vector<char>() : buried_leaves(h, now, moved);
    if (std::find(buried.begin(), buried.end(), 1) != buried.end()) at_first_bounce(judge, &buried);
    else judge();
}

std::vector<int> AdjustSystem::run() {
    std::vector<int> recheck;
    std::vector<int> recompute = classify_links();
    c_.lap("classify");
    keep_links_rays_meet(recompute);
    c_.lap("probe");
    recompute_links(recompute, recheck);
    c_.lap("recompute");
    link_changed();
    c_.lap("relink");
    redecide_enclosures();
    return recheck;
}

// A moved object's inner links turn with it, env-obj links go (made anew by link_changed),
// env-env links are pruned by the old and new boxes' outcodes (3.3).
std::vector<int> AdjustSystem::classify_links() {
    const Change& ch = c_.change;
    Hierarchy& h = c_.h;
    LinkStore& links = c_.links;
    Stats& s = c_.stats;
    std::vector<int> recompute;
    const size_t nlinks = links.size();
    // The outcode test of every link whose ends both stay, in parallel (it reads the ends'
    // boxes, far apart in memory); the boxes' union first, beyond which lies beyond every box.
    Aabb all;
    for (const Aabb& c : ch.clips) all.grow(c);
    std::vector<char> meets(nlinks, 0);
    parallel_for(nlinks, c_.settings.threads, [&](size_t i) {
        const Link& l = links[i];
        if (l.dead || ch.inX[l.src] || ch.inX[l.rcv]) return;
        const Aabb& a = h.nodes[l.src].box;
        const Aabb& b = h.nodes[l.rcv].box;
        if (ch.clips.empty() || (outcode(a, all) & outcode(b, all)) != 0) return;
        for (const Aabb& c : ch.clips)
            if ((outcode(a, c) & outcode(b, c)) == 0) { meets[i] = 1; return; }
    }, 4096);
    for (size_t i = 0; i < nlinks; ++i) {
        Link& l = links[i];
        if (l.dead) continue;
        if (ch.inX[l.src] || ch.inX[l.rcv]) {
            const Node& a = h.nodes[l.src];
            const Node& b = h.nodes[l.rcv];
            // Obj-obj (both ends inside one moved object): a rigid move keeps its form
            // factor; only the direction turns.
            if (a.object >= 0 && a.object == b.object && ch.moved[a.object]) {
                l.dir = ch.moves.at(a.object).dir(l.dir);
                l.ray_count = -1;  // its rays moved with it: the record is of other segments
                continue;
            }
            if (l.active) ++s.obj_env_links_removed;
            if (l.parent < 0 || (!ch.inX[links[l.parent].src] && !ch.inX[links[l.parent].rcv])) links.kill(h, int(i));
            continue;
        }
        // Env-env: 3.3 pruning with the old and new boxes of every moved object.
        ++s.env_env_links_tested;
        if (!meets[i]) { ++s.env_env_links_rejected; continue; }
        recompute.push_back(int(i));
    }
    return recompute;
}

void AdjustSystem::keep_links_rays_meet(std::vector<int>& recompute) {
    const Change& ch = c_.change;
    const Hierarchy& h = c_.h;
    // Of the links the outcode test kept, only those with a ray through an old or new box
    // of a moved object can have changed. Every ray joins a point of one end's bounding
    // sphere to a point of the other's, so it stays within max(radius) of the segment between
    // the centres, and within the convex hull of the ends' boxes (meets_shaft, tighter where
    // one end is much larger than the other): a box both miss meets no ray.
    std::vector<char> may(recompute.size(), 0);
    parallel_for(recompute.size(), c_.settings.threads, [&](size_t k) {
        const Link& l = c_.links[recompute[k]];
        const Node& a = h.nodes[l.src];
        const Node& b = h.nodes[l.rcv];
        const double r = std::max(a.radius, b.radius) + 1e-5;
        for (const Aabb& c : ch.clips)
            if (c.grown(r).meets_segment(a.center, b.center) && c.meets_shaft(a.box, b.box)) { may[k] = 1; break; }
    }, 256);
    size_t kept = 0;
    for (size_t k = 0; k < recompute.size(); ++k)
        if (may[k]) recompute[kept++] = recompute[k];
    c_.stats.env_env_links_rays_clear += int64_t(recompute.size() - kept);
    recompute.resize(kept);
}

void AdjustSystem::recompute_links(std::vector<int>& recompute, std::vector<int>& recheck) {
    LinkStore& links = c_.links;
    Stats& s = c_.stats;
    // Every gathered link kept is evaluated at once, and every occluded one (the view may
    // open). Only the rays through a moved box are cast (replay). One whose evaluation comes
    // out the same is left as it is.
    // History links are not gathered: they are left stale, and evaluated when un-refinement
    // asks about them and a judgement without rays says they might come back
    // (Refinement::freshen_stale; docs/decisions.md, "History links are left stale").
    {
        size_t kept = 0;
        for (int id : recompute) {
            Link& l = links[id];
            if (!l.active && !l.occluded) {
                l.stale = true;
                ++s.history_links_stale;
            } else {
                recompute[kept++] = id;
            }
        }
        recompute.resize(kept);
    }
    Refinement refining(c_.refining);
    const LinkEvaluator e = refining.evaluator();
    std::vector<Link> fresh(recompute.size());
    parallel_for(recompute.size(), c_.settings.threads,
                 [&](size_t k) { fresh[k] = e.reevaluate(links[recompute[k]]); }, 16);
    for (size_t k = 0; k < recompute.size(); ++k) {
        Link& l = links[recompute[k]];
        if (l.dead) continue;
        const Link& f = fresh[k];
        ++s.env_env_links_recomputed;
        if (f.K == l.K && f.K_unoccluded == l.K_unoccluded && f.vis == l.vis && f.dK == l.dK && f.partial == l.partial &&
            f.blocked == l.blocked && f.must_refine == l.must_refine) {
            l.ray_count = f.ray_count;  // what the rays met may differ where it changed nothing
            l.ray_blocked = f.ray_blocked;
            l.ray_self = f.ray_self;
            continue;
        }
        const bool changed = f.K != l.K || f.partial != l.partial;
        refining.refresh(recompute[k], f);
        l.rejudge = true;
        const bool transports = f.transports();
        if (l.active && !transports) {
            links.deactivate(c_.h, recompute[k]);  // newly fully occluded: a new shadow
            l.occluded = true;
        } else if (l.occluded && transports) {
            links.activate(c_.h, recompute[k]);    // the view opened: an old shadow goes
        }
        // Its history may coarsen back (an old shadow gone): the refined-from links up
        // the chain are asked again, coarsest first (paper 3.4).
        if (changed)
            for (int p = l.parent; p >= 0; p = links[p].parent) recheck.push_back(p);
    }
    std::sort(recheck.begin(), recheck.end());
    recheck.erase(std::unique(recheck.begin(), recheck.end()), recheck.end());
}

void AdjustSystem::link_changed() {
    const Change& ch = c_.change;
    const Hierarchy& h = c_.h;
    // Env-obj links created anew: the moved clusters against the environment, top-down,
    // cluster pairs first (this also links an object where it had no link before).
    std::set<std::pair<int, int>> pairs;
    std::vector<Candidate> wave;
    // A self-link seed (an added subtree) makes every pair of siblings inside its node when
    // Refinement::link_from expands it: a pair made again from a chain, or a seed inside
    // another seed's subtree, would transport the same light twice.
    std::vector<char> seeded(h.nodes.size(), 0);
    for (const Candidate& c : ch.seeds)
        if (c.src == c.rcv) seeded[c.src] = 1;
    auto inside_seed = [&](int n) {
        for (int a = n; a >= 0; a = h.nodes[a].parent)
            if (seeded[a]) return true;
        return false;
    };
    for (const auto& chain : ch.chains)
        for (size_t i = 0; i + 1 < chain.size(); ++i) {
            if (inside_seed(chain[i])) continue;
            for (int sib : h.nodes[chain[i]].children) {
                if (sib == chain[i + 1]) continue;
                if (pairs.insert({sib, chain[i + 1]}).second) wave.push_back({sib, chain[i + 1], -1});
                if (pairs.insert({chain[i + 1], sib}).second) wave.push_back({chain[i + 1], sib, -1});
            }
        }
    // Added objects: their own inside (a self-link, expanded by Refinement::link_from) and,
    // unclustered, their surfaces with every other one.
    for (const Candidate& c : ch.seeds) {
        if (c.src == c.rcv && h.nodes[c.src].parent >= 0 && inside_seed(h.nodes[c.src].parent)) continue;
        if (pairs.insert({c.src, c.rcv}).second) wave.push_back(c);
    }
    // Unclustered scenes have no object cluster: link each moved surface with the rest.
    for (auto& [obj, pose] : ch.moves) {
        (void)pose;
        if (h.object_node[obj] >= 0) continue;
        for (int c : h.nodes[h.root].children) {
            if (ch.inX[c]) continue;
            for (const Primitive& p : h.prims)
                if (p.object == obj)
                    for (int sidx : {p.front, p.back})
                        if (sidx >= 0) {
                            int r = h.surfaces[sidx].root;
                            wave.push_back({c, r, -1});
                            wave.push_back({r, c, -1});
                        }
        }
    }
    // These links stand for a full solve's first linking of the new scene, so they are judged
    // as it judges: on the scene-wide threshold, and with what the move buried (the floor under
    // the box's new place) at the radiance that linking gives it (emission and the lamps' first
    // bounce), not at the radiance solved when it was open (Solver::update_resolve says why).
    // In a lit scene the lamps' direct terms are still the ones before the move here: the
    // solver lights the new placement later.
    Refinement::Context first_linking = c_.refining;
    first_linking.threshold.light_known = false;
    judge_where_buried(h, ch.now, ch.moved, c_.at_first_bounce,
                       [&] { Refinement(first_linking).link_from(std::move(wave)); });
}

void AdjustSystem::redecide_enclosures() {
    const Change& ch = c_.change;
    const Hierarchy& h = c_.h;
    Enclosure& e = c_.enclosure;
    e.fit(h);  // the elements split since the last closure pass take their parents' answers
    // A move can open or close a pocket (the floor a box stood on now sees the sky).
    // Every decider of an enclosure answer asks again, but casts again only the escape
    // rays that pass through a moved object's old or new box (all of them if it moved).
    const std::vector<int> deciders = e.deciders(h);
    parallel_for(deciders.size(), c_.settings.threads, [&](size_t k) {
        const int d = deciders[k];
        const bool moved = ch.moved[h.nodes[d].object];
        if (moved) e.forget(d);
        e.decide({h, c_.refining.vis, c_.settings}, d, moved ? nullptr : &ch.clips);
    }, 16);
    e.follow_deciders(h);
}

}  // namespace radiosity
