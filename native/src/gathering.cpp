// Gathering with push-pull (paper 2): every receiver gathers through its links from the
// previous radiances (Jacobi), irradiance is pushed down the hierarchy, reflected at the
// leaves and radiance pulled back up area-weighted. The sweeps run on a gather plan
// (gather_plan.h), a compact copy of links and trees made after collect().
#include "radiosity/gathering.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "radiosity/held_bytes.h"
#include "radiosity/parallel.h"
#include "radiosity/run_clock.h"

namespace radiosity {

void Gathering::collect(const Hierarchy& h) {
    leaves_.clear();
    for (size_t i = 0; i < h.nodes.size(); ++i) {
        const Node& n = h.nodes[i];
        if (!n.dead && !n.is_cluster() && n.is_leaf()) leaves_.push_back(int(i));
    }
    enclosure_.fit(h);
    plan_.invalidate();  // links, nodes or materials may have changed since it was built
}

std::vector<int> Gathering::enclosed_leaves() const {
    std::vector<int> out;
    for (int leaf : leaves_)
        if (enclosure_.enclosed(leaf) == 1) out.push_back(leaf);
    return out;
}

double Gathering::bytes(size_t links, size_t nodes) const {
    return held_bytes(leaves_) + enclosure_.bytes(nodes) + plan_.bytes(links, nodes);
}

void Gathering::ensure_plan(const Context& c, bool radiometry) {
    const bool valid = plan_.valid(c.links.size(), c.h.nodes.size());
    if (valid && (!radiometry || plan_.has_radiometry())) return;
    const auto t0 = std::chrono::steady_clock::now();
    if (!valid) {
        plan_.build(c.h, c.links, c.settings.threads);
        ++c.stats.gather_plans;
    }
    if (radiometry) {
        enclosure_.fit(c.h);  // nodes made since collect take their parents' factors
        plan_.prepare_radiometry(c.h, c.links, enclosure_, [&c](int id) { return c.direct_light.direct(id); },
                                 c.settings.threads);
    }
    c.stats.seconds_gather_plan += RunClock::seconds_since(t0);
}

void Gathering::sweep(const Context& c) {
    ensure_plan(c, true);
    plan_.sweep(false, nullptr, c.settings.threads);
    plan_.write_back(c.h, c.links, c.settings.threads);
}

// A unit sweep uses the plan when there is one; else it walks the hierarchy (a plan would
// cost as much to build as that one sweep, and iterate_to builds its own after the closure
// pass).
CouplingSums Gathering::sum_couplings(const Context& c) {
    CouplingSums sums;
    sums.reset(c.h.nodes.size());
    if (!plan_.valid(c.links.size(), c.h.nodes.size())) {
        coupling_sums(c.h, c.links, sums, c.settings.threads);
        return sums;
    }
    ensure_plan(c, false);
    plan_.sweep(true, &sums, c.settings.threads);
    plan_.write_back(c.h, c.links, c.settings.threads);
    return sums;
}

int Gathering::iterate_to(const Context& c, double tolerance, int max_iterations, double reference,
                          const std::function<void()>& check_cancel, const std::function<void(double)>& progress) {
    ensure_plan(c, true);
    const int64_t gathered = plan_.link_count();
    double prev = -1;
    const double scale = std::max(reference, 1e-300);
    // The sweeps run on the plan; the nodes get the radiances once, after the last one. When
    // a cancel unwinds through here they get them too (on this thread: nothing may throw
    // while unwinding), so the nodes never hold a half-copied state.
    struct WriteBackOnUnwind {
        GatherPlan& plan;
        const Context& c;
        ~WriteBackOnUnwind() { plan.write_back(c.h, c.links, 1); }
    } unwind{plan_, c};
    int sweeps = 0;
    bool converged = false;
    while (sweeps < max_iterations && !converged) {
        check_cancel();
        const auto t0 = std::chrono::steady_clock::now();
        double delta = plan_.sweep(false, nullptr, c.settings.threads) / scale;
        c.stats.seconds_sweeps += RunClock::seconds_since(t0);
        ++c.stats.iterations;
        c.stats.link_sweeps += gathered;
        // Remaining error of a geometric iteration: delta * q / (1 - q), q the observed
        // contraction; this keeps the stop honest at reflectance near 1.
        double q = prev > 0 ? std::min(delta / prev, 0.9999) : 0.9;
        double remaining = delta * q / (1.0 - q);
        c.stats.residual = remaining;
        prev = delta;
        ++sweeps;
        progress(std::min(1.0, double(sweeps) / max_iterations));
        converged = delta == 0 || (sweeps >= 2 && remaining < tolerance);
    }
    plan_.write_back(c.h, c.links, c.settings.threads);
    if (!converged) c.stats.iteration_capped = true;
    return sweeps;
}

void Gathering::pull_up_clusters(Hierarchy& h) {
    // Children clusters always have larger ids than their parents: one reverse pass.
    for (int i = int(h.nodes.size()) - 1; i >= 0; --i) {
        Node& c = h.nodes[i];
        if (!c.is_cluster()) continue;
        Rgb sum, lo = Rgb::all(1e300), hi = Rgb::all(-1e300);
        double area = 0;
        c.S.fill(Rgb{});
        for (int k : c.children) {
            const Node& n = h.nodes[k];
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
// get their couplings corrected toward a sum of 1. Leaves that see open space are left as
// computed.
void Gathering::set_closure(const Context& c, const CouplingSums& sums, const std::function<void(int)>& decide_enclosed) {
    enclosure_.fit(c.h);
    parallel_for(leaves_.size(), c.settings.threads, [&](size_t i) {
        const int leaf = leaves_[i];
        const Node& n = c.h.nodes[leaf];
        const double f = sums.total[leaf], own = sums.own[leaf], inherited = f - own;
        ClosureFactors k;  // none: unit factors, no fill
        // closure_factors' range: a sum far off 1 (DRAFT's can be) is a missing link, not a
        // small error.
        if (c.settings.closure_rays > 0 && f > 0.25 && f < 4.0) {
            if (enclosure_.enclosed(leaf) < 0) decide_enclosed(leaf);
            if (enclosure_.enclosed(leaf) == 1) {
                // The leaf's own links were evaluated for it; links at its ancestors and
                // clusters carry a coupling averaged over a larger receiver whose view may
                // be wider (a ceiling patch in the gap behind a lamp sees the lamp through
                // its own link and a sliver of the room, where the ceiling above it sees
                // all the room). So an excess (sum > 1) is taken from those inherited
                // couplings: scaling all alike would dim the lamp's exact link with them, and
                // by an amount that depends on how far an update refined the room's links.
                // When the own links alone pass 1 (a near-field link's estimate over a large
                // patch can), they are the excess: scaled to 1, the inherited ones dropped.
                // inherited > 0 whenever own < 1 < f.
                // A shortfall: what the links miss is taken to see surfaces as bright as
                // the leaf itself. Scaling every coupling by 1 / f would create light: a
                // leaf's exact links to a lamp (far brighter than the room) would grow with
                // the missing ones, and a closed room absorb more power than its lamps emit.
                // A furnace stays exact: there every radiance is the leaf's own. (Figures:
                // docs/decisions.md, "Closure correction at leaves" and "Figures behind code
                // comments".)
                k = closure_factors(own, inherited);  // gather_plan.h
            }
        }
        // Guard, open or closed: the iteration contracts only if every leaf reflects less
        // than it gathers (rho * sum of couplings < 1). Sums above 1 (coincident faces, a
        // pair linked twice) at reflectance near 1 would diverge; such a leaf is scaled back
        // to a gain just below 1.
        constexpr double kMaxGain = 0.9995;
        const double gain = n.rho.max() * (own * k.c_own + inherited * k.c_inherited + k.fill);
        if (gain > kMaxGain) {
            k.c_inherited *= kMaxGain / gain;
            k.c_own *= kMaxGain / gain;
            k.fill *= kMaxGain / gain;
        }
        enclosure_.set_factors(leaf, k);
    }, 32);
}

}  // namespace radiosity
