// Gathering with push-pull (paper 2): every receiver gathers through its links from the
// previous radiances (Jacobi), irradiance is pushed down the hierarchy, reflected at the
// leaves and radiance pulled back up area-weighted. The sweeps run on a gather plan
// (gather_plan.h), a compact copy of links and trees made after collect_receivers().
#include <algorithm>
#include <chrono>
#include <cmath>

#include "radiosity/parallel.h"
#include "radiosity/solver.h"

namespace radiosity {

void Solver::collect_receivers() {
    receivers_.clear();
    leaves_.clear();
    for (size_t i = 0; i < h_.nodes.size(); ++i) {
        const Node& n = h_.nodes[i];
        if (n.dead) continue;
        if (!n.in_links.empty()) receivers_.push_back(int(i));
        if (!n.is_cluster() && n.is_leaf()) leaves_.push_back(int(i));
    }
    // The direct light of the leaves lacking it: new ones, and every one after a light changed
    // or objects moved.
    direct_light_.prepare(h_, light_sight(), leaves_, edits_.poses(), light_replay());
    plan_.invalidate();  // links, nodes or materials may have changed since it was built
}

void Solver::ensure_plan(bool radiometry) {
    const bool valid = plan_.valid(links_.size(), h_.nodes.size());
    if (valid && (!radiometry || plan_.has_radiometry())) return;
    const auto t0 = std::chrono::steady_clock::now();
    if (!valid) {
        plan_.build(h_, links_, settings_.threads);
        ++stats_.gather_plans;
    }
    if (radiometry) plan_.prepare_radiometry(h_, links_, [this](int id) { return direct_light_.direct(id); }, settings_.threads);
    stats_.seconds_gather_plan += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// One Jacobi sweep. With unit=true every sender counts as radiance 1 and the per-leaf sum
// of form factors is written to fsum instead (used by the closure correction). A unit sweep
// uses the plan when there is one; else it walks the hierarchy (a plan would cost as much to
// build as that one sweep, and iterate_to builds its own after the closure pass).
double Solver::sweep(bool unit, CouplingSums* sums) {
    if (unit && !plan_.valid(links_.size(), h_.nodes.size())) {
        coupling_sums(h_, links_, *sums, settings_.threads);
        return 0.0;
    }
    ensure_plan(!unit);
    const double d = plan_.sweep(unit, sums, settings_.threads);
    plan_.write_back(h_, links_, settings_.threads);
    return d;
}

int Solver::iterate_to(double tolerance, int max_iterations, double p0, double p1) {
    collect_receivers();
    ensure_plan(true);
    const int64_t gathered = plan_.link_count();
    double prev = -1;
    const double scale = std::max(L_ref_, 1e-300);
    // The sweeps run on the plan; the nodes get the radiances once, after the last one. When
    // a cancel unwinds through here they get them too (on this thread: nothing may throw
    // while unwinding), so the nodes never hold a half-copied state.
    struct WriteBackOnUnwind {
        Solver& s;
        ~WriteBackOnUnwind() { s.plan_.write_back(s.h_, s.links_, 1); }
    } unwind{*this};
    int sweeps = 0;
    bool converged = false;
    while (sweeps < max_iterations && !converged) {
        check_cancel();
        const auto t0 = std::chrono::steady_clock::now();
        double delta = plan_.sweep(false, nullptr, settings_.threads) / scale;
        stats_.seconds_sweeps += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        ++stats_.iterations;
        stats_.link_sweeps += gathered;
        // Remaining error of a geometric iteration: delta * q / (1 - q), q the observed
        // contraction; this keeps the stop honest at reflectance near 1.
        double q = prev > 0 ? std::min(delta / prev, 0.9999) : 0.9;
        double remaining = delta * q / (1.0 - q);
        stats_.residual = remaining;
        prev = delta;
        ++sweeps;
        set_progress(p0 + (p1 - p0) * std::min(1.0, double(sweeps) / max_iterations));
        converged = delta == 0 || (sweeps >= 2 && remaining < tolerance);
    }
    plan_.write_back(h_, links_, settings_.threads);
    if (!converged) stats_.iteration_capped = true;
    return sweeps;
}

// Clusters' radiance, range and direction bins from their children, over the nodes (the
// gather plan does this in its own arrays; this serves code that sets element radiances
// outside a sweep: lights.cpp at_first_bounce).
void Solver::pull_up_clusters() {
    // Children clusters always have larger ids than their parents: one reverse pass.
    for (int i = int(h_.nodes.size()) - 1; i >= 0; --i) {
        Node& c = h_.nodes[i];
        if (!c.is_cluster()) continue;
        Rgb sum, lo = Rgb::all(1e300), hi = Rgb::all(-1e300);
        double area = 0;
        c.S.fill(Rgb{});
        for (int k : c.children) {
            const Node& n = h_.nodes[k];
            if (n.is_cluster()) {
                for (int b = 0; b < kBins; ++b) c.S[b] += n.S[b];
            } else {
                for (int a = 0; a < 3; ++a) {
                    double v = n.normal[a] * n.area;
                    c.S[bin_of(a, v)] += n.L * std::fabs(v);
                }
            }
            sum += n.L * n.area;
            area += n.area;
            lo = cmin(lo, n.Lmin);
            hi = cmax(hi, n.Lmax);
        }
        c.L = area > 0 ? sum / area : Rgb{};
        c.Lmin = c.children.empty() ? Rgb{} : lo;
        c.Lmax = c.children.empty() ? Rgb{} : hi;
    }
}

// Closure correction: a leaf from which no escape ray finds open space is enclosed, so its
// form factors must sum to 1; the analytic kernels with sampled visibility miss that by a
// little, and at reflectance near 1 the error is amplified 1/(1 - rho) times. Such leaves
// get their couplings scaled by 1 / sum. Leaves that see open space are left as computed.
// A leaf decides with its own escape rays the first time it is a leaf in a closure pass;
// its children inherit the answer (and the decider) when it splits.
void Solver::compute_closure() {
    for (int pass = 0;; ++pass) {
        collect_receivers();
        CouplingSums sums;
        sums.reset(h_.nodes.size());
        sweep(true, &sums);
        lap("closure sums");
        parallel_for(leaves_.size(), settings_.threads, [&](size_t i) {
            Node& n = h_.nodes[leaves_[i]];
            const double f = sums.total[leaves_[i]], own = sums.own[leaves_[i]], inherited = f - own;
            n.closure = n.closure_own = 1.0;
            n.closure_fill = 0.0;
            if (settings_.closure_rays > 0 && f > 0.25 && f < 4.0) {  // closure_factors' range  // far off 1 (DRAFT can be): a missing link, not a small error
                if (n.enclosed < 0) decide_enclosed(leaves_[i], nullptr);
                if (n.enclosed == 1) {
                    // The leaf's own links were evaluated for it; links at its ancestors and
                    // clusters carry a coupling averaged over a larger receiver whose view may
                    // be wider (a ceiling patch in the gap behind a lamp sees the lamp through
                    // its own link and a sliver of the room, where the ceiling above it sees
                    // all the room). So an excess (sum > 1) is taken from those inherited
                    // couplings; scaling all alike dimmed the lamp's exact link with them (such
                    // patches 6 % dark, and by how much depended on how far an update had
                    // refined the room's links: 0.9 % NRMSE between an update and a full solve
                    // of the box room). When the own links alone pass 1 (a near-field link's
                    // estimate over a large patch can), they are the excess: scaled to 1, the
                    // inherited ones dropped (a DRAFT ceiling patch behind a lamp got 4.8
                    // instead of 5.9, rho x lamp, when all were scaled alike). inherited > 0
                    // whenever own < 1 < f.
                    // A shortfall: what the links miss is taken to see surfaces as bright as
                    // the leaf itself. Scaling every coupling by 1 / f instead created light: a
                    // leaf's exact links to a lamp (radiance 12 against ~0.4 for the room) grew
                    // with the missing ones, and the closed rooms absorbed 4-14 % more power
                    // than their lamps emit (bench/results/brightness.md). A furnace stays
                    // exact: there every radiance is the leaf's own.
                    const ClosureFactors c = closure_factors(own, inherited);  // gather_plan.h
                    n.closure_own = c.c_own;
                    n.closure = c.c_inherited;
                    n.closure_fill = c.fill;
                }
            }
            // Guard, open or closed: the iteration contracts only if every leaf reflects less
            // than it gathers (rho * sum of couplings < 1). Sums above 1 (coincident faces, a
            // pair linked twice) at reflectance near 1 diverged (fuzzer: 5e22, then inf after
            // a move); such a leaf is scaled back to a gain just below 1.
            constexpr double kMaxGain = 0.9995;
            const double gain = n.rho.max() * (own * n.closure_own + inherited * n.closure + n.closure_fill);
            if (gain > kMaxGain) {
                n.closure *= kMaxGain / gain;
                n.closure_own *= kMaxGain / gain;
                n.closure_fill *= kMaxGain / gain;
            }
        }, 32);
        lap("closure decide");
        const bool split = settings_.closure_rays > 0 && pass < settings_.closure_refine_passes && closure_refine(sums.total);
        lap("closure split");
        if (!split) break;
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
        Vec3 o = n.poly.sample(rng.next(), rng.next()) + n.normal * lift;
        rays.emplace_back(o, o + d * far);
    }
}

// Decides (or, after a move, re-decides) whether a node's escape rays find open space. With
// `moved_boxes`, the node was decided before and did not move itself: only rays through a
// moved object's old or new box can have changed outcome.
void Solver::decide_enclosed(int id, const std::vector<Aabb>* moved_boxes) {
    Node& n = h_.nodes[id];
    std::vector<std::pair<Vec3, Vec3>> rays;
    escape_rays(n, rays);
    auto meets = [&](int r) { return meets_any(*moved_boxes, rays[r].first, rays[r].second); };
    if (moved_boxes && n.enclosed == 1) {
        for (int r = 0; r < int(rays.size()); ++r)
            if (meets(r) && !vis_->occluded(rays[r].first, rays[r].second, 0.0)) {
                n.enclosed = 0;
                n.escape_ray = int8_t(r);
                return;
            }
        return;  // every ray still blocked
    }
    if (moved_boxes && n.enclosed == 0 && n.escape_ray >= 0 && !meets(n.escape_ray)) return;  // witness still clear
    n.decider = id;
    for (int r = 0; r < int(rays.size()); ++r)
        if (!vis_->occluded(rays[r].first, rays[r].second, 0.0)) {
            n.enclosed = 0;
            n.escape_ray = int8_t(r);
            return;
        }
    n.enclosed = 1;
    n.escape_ray = -1;
}

}  // namespace radiosity
