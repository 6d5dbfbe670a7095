// Gathering with push-pull (paper 2): every receiver gathers through its links from the
// previous radiances (Jacobi), irradiance is pushed down the hierarchy, reflected at the
// leaves and radiance pulled back up area-weighted.
#include <algorithm>
#include <cmath>

#include "radiosity/parallel.h"
#include "radiosity/solver.h"
#include "radiosity/transfer.h"

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
    light_prepare();  // lights.cpp: direct light of new leaves
}

void Solver::push_down(int id, Rgb acc, bool unit, std::vector<double>* fsum, double& delta) {
    Node& n = h_.nodes[id];
    if (!n.in_links.empty()) acc += n.G;
    if (n.children.empty()) {
        if (unit) {
            (*fsum)[id] = acc.mean();
            return;
        }
        Rgb Lnew = n.emission + n.rho * (acc * n.closure + light_direct(id));  // lights.cpp
        delta = std::max(delta, std::fabs((Lnew - n.L).max()));
        delta = std::max(delta, std::fabs((n.L - Lnew).max()));
        n.L = Lnew;
        n.Lmin = n.Lmax = Lnew;
        return;
    }
    Rgb sum, lo = Rgb::all(1e300), hi = Rgb::all(-1e300);
    double area = 0;
    for (int c : n.children) {
        push_down(c, acc, unit, fsum, delta);
        if (unit) continue;
        const Node& k = h_.nodes[c];
        sum += k.L * k.area;
        area += k.area;
        lo = cmin(lo, k.Lmin);
        hi = cmax(hi, k.Lmax);
    }
    if (unit) return;
    n.L = area > 0 ? sum / area : n.emission;
    n.Lmin = lo;
    n.Lmax = hi;
}

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

// One Jacobi sweep. With unit=true every sender counts as radiance 1 and the per-leaf sum
// of form factors is written to fsum instead (used by the closure correction).
double Solver::sweep(bool unit, std::vector<double>* fsum) {
    // 1. Gather through links, in parallel over receivers (each writes only its own data).
    parallel_for(receivers_.size(), settings_.threads, [&](size_t i) {
        Node& q = h_.nodes[receivers_[i]];
        Rgb g;
        for (int li : q.in_links) {
            Link& l = links_[li];
            Rgb Ls = unit ? Rgb::all(1.0) : sender_radiance(h_, l);
            Rgb v = Ls * l.K;
            if (q.is_cluster()) l.value = v;
            else g += v;
        }
        q.G = g;
    }, 64);
    // 2. Per surface: flux arriving through cluster links above it, times its own cosine
    //    (oriented clusters), then push-pull down its quadtree.
    std::vector<double> deltas(h_.surfaces.size(), 0.0);
    parallel_for(h_.surfaces.size(), settings_.threads, [&](size_t s) {
        const int root = h_.surfaces[s].root;
        if (h_.nodes[root].dead) return;  // of a removed object
        const Vec3 n = h_.nodes[root].normal;
        Rgb acc;
        for (int a : h_.ancestors_of_surface(int(s)))
            for (int li : h_.nodes[a].in_links) {
                const Link& l = links_[li];
                double c = -dot(n, l.dir);
                if (c > 0) acc += l.value * c;
            }
        push_down(root, acc, unit, fsum, deltas[s]);
    }, 64);
    if (unit) return 0.0;
    pull_up_clusters();
    double d = 0;
    for (double x : deltas) d = std::max(d, x);
    return d;
}

int Solver::iterate_to(double tolerance, int max_iterations, double p0, double p1) {
    collect_receivers();
    double prev = -1;
    const double scale = std::max(L_ref_, 1e-300);
    int it = 0;
    for (; it < max_iterations; ++it) {
        check_cancel();
        double delta = sweep(false, nullptr) / scale;
        ++stats_.iterations;
        // Remaining error of a geometric iteration: delta * q / (1 - q), q the observed
        // contraction; this keeps the stop honest at reflectance near 1.
        double q = prev > 0 ? std::min(delta / prev, 0.9999) : 0.9;
        double remaining = delta * q / (1.0 - q);
        stats_.residual = remaining;
        prev = delta;
        set_progress(p0 + (p1 - p0) * std::min(1.0, double(it + 1) / max_iterations));
        if (delta == 0 || (it >= 1 && remaining < tolerance)) return it + 1;
    }
    stats_.iteration_capped = true;
    return it;
}

// Closure correction: a leaf from which no escape ray finds open space is enclosed, so its
// form factors must sum to 1; the analytic kernels with sampled visibility miss that by a
// little, and at reflectance near 1 the error is amplified 1/(1 - rho) times. Such leaves
// get their couplings scaled by 1 / sum. Leaves that see open space are left as computed.
// A leaf decides with its own escape rays the first time it is a leaf in a closure pass;
// its children inherit the answer (and the decider) when it splits.
void Solver::compute_closure() {
    if (settings_.closure_rays <= 0) return;
    collect_receivers();
    std::vector<double> fsum(h_.nodes.size(), 0.0);
    sweep(true, &fsum);
    parallel_for(leaves_.size(), settings_.threads, [&](size_t i) {
        Node& n = h_.nodes[leaves_[i]];
        n.closure = 1.0;
        double f = fsum[leaves_[i]];
        if (!(f > 0.25 && f < 4.0)) return;  // far off 1 (DRAFT can be): a missing link, not a small error
        if (n.enclosed < 0) decide_enclosed(leaves_[i], nullptr);
        if (n.enclosed == 1) n.closure = 1.0 / f;
    }, 32);
}

// The escape rays of a node: cosine-distributed from random points of its polygon, lifted
// off it, reaching beyond the scene. Deterministic per node key.
void Solver::escape_rays(const Node& n, std::vector<std::pair<Vec3, Vec3>>& rays) const {
    const double far = 4.0 * h_.scene_diag;
    const double lift = 1e-5 * h_.scene_diag;  // off its own surface; tnear 0 sees neighbours
    Rng rng(Hierarchy::mix(settings_.seed, n.key));
    Vec3 t = std::fabs(n.normal.x) > 0.5 ? Vec3{0, 1, 0} : Vec3{1, 0, 0};
    Vec3 u = normalize(cross(n.normal, t)), v = cross(n.normal, u);
    rays.clear();
    for (int r = 0; r < settings_.closure_rays; ++r) {
        double r1 = rng.next(), r2 = rng.next();
        double phi = 2 * kPi * r1, sr = std::sqrt(r2);
        Vec3 d = u * (std::cos(phi) * sr) + v * (std::sin(phi) * sr) + n.normal * std::sqrt(1 - r2);
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
    auto meets = [&](int r) {
        for (const Aabb& b : *moved_boxes)
            if (b.meets_segment(rays[r].first, rays[r].second)) return true;
        return false;
    };
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
