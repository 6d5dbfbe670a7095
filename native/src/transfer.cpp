#include "radiosity/transfer.h"

#include <algorithm>
#include <cmath>

#include "radiosity/random.h"

namespace radiosity {

double unoccluded_coupling(const Poly& rcv, const Vec3& rcv_n, const Node& src) {
    Cubature cub = receiver_cubature(rcv, src.poly.v[0], src.normal);
    double k = 0;
    for (int j = 0; j < cub.n; ++j) k += cub.w[j] * point_polygon_form_factor(cub.p[j], rcv_n, src.poly, src.normal);
    return k;
}

double unoccluded_coupling(const Poly& rcv, const Vec3& rcv_n, const Node& src, int depth) {
    if (depth <= 0) return unoccluded_coupling(rcv, rcv_n, src);
    const double area = rcv.area();
    if (!(area > 0)) return 0.0;
    double k = 0;
    for (int c = 0; c < 4; ++c) {
        const Poly child = rcv.child(c);
        k += child.area() * unoccluded_coupling(child, rcv_n, src, depth - 1);
    }
    return k / area;
}

Rgb sender_radiance(const Hierarchy& h, const Link& l) {
    const Node& src = h.nodes[l.src];
    if (!l.samples.empty()) {
        Rgb acc;
        double w = 0;
        for (const auto& s : l.samples) {
            acc += h.nodes[size_t(h.live_element(s.first))].L * double(s.second);
            w += s.second;
        }
        return acc / w;
    }
    if (!src.is_cluster()) return src.L;
    const Vec3& d = l.dir;
    Rgb num;
    double den = 0;
    for (int a = 0; a < 3; ++a) {
        double w = d[a] * d[a];
        if (w <= 0) continue;
        int b = bin_of(a, d[a]);
        num += src.S[b] * w;
        den += src.W[b] * w;
    }
    return den > 0 ? num / den : src.L;
}

namespace {

// Casts every ray through Visibility and keeps the outcomes for the link (Link::ray_count,
// ray_blocked, ray_self).
struct RayLog {
    const Visibility& vis;
    mutable uint64_t blocked = 0, self = 0;
    mutable int n = 0;  // rays cast so far
    bool note(bool occluded) const {
        if (occluded && n < 64) blocked |= uint64_t(1) << n;
        ++n;
        return occluded;
    }
    bool note_self(bool hidden) const {  // about the last ray
        if (hidden && n >= 1 && n <= 64) self |= uint64_t(1) << (n - 1);
        return hidden;
    }
    bool occluded(const Vec3& a, const Vec3& b) const { return note(vis.occluded(a, b)); }
    // Whether the first thing on a -> b (beyond `near`) belongs to `object`. Asked only of
    // a blocked ray, its segment reversed.
    bool hidden_by(const Vec3& a, const Vec3& b, double near, int object) const {
        return note_self(vis.hit_object(a, b, near, nullptr) == object);
    }
    void store(Link& l) const {
        l.ray_count = n <= 64 ? n : -1;
        l.ray_blocked = blocked;
        l.ray_self = self;
    }
};

// RayLog that takes a ray's outcome from an earlier record of the same link when the ray
// passes through no box where the geometry changed since (reevaluate_link): the segments
// are the same (same ends, same seed), and so is everything along them.
struct RayReplay : RayLog {
    const Link& old;
    const std::vector<Aabb>& changed;
    mutable bool cast = false;  // the last ray was cast, not replayed
    bool occluded(const Vec3& a, const Vec3& b) const {
        const int k = n;
        cast = k >= old.ray_count || meets_any(changed, a, b);
        return note(cast ? vis.occluded(a, b) : ((old.ray_blocked >> k) & 1) != 0);
    }
    bool hidden_by(const Vec3& a, const Vec3& b, double near, int object) const {
        if (cast) return RayLog::hidden_by(a, b, near, object);
        return note_self(((old.ray_self >> (n - 1)) & 1) != 0);
    }
};

// Latin hypercube strata for n samples: coordinate d of sample k is (perm_d[k] + jitter) / n,
// every coordinate permuted on its own. Each coordinate then puts one sample in each 1/n
// interval (a plain draw clumps), so a link's few rays cover its ends evenly and a cluster
// link's estimate varies less from seed to seed than with independent draws. Never worse
// than independent draws beyond a factor n / (n - 1) in variance.
class LatinHypercube {
public:
    static constexpr int kDims = 6;  // at most, per ray: surface pick and a point, at each end
    // `dims` coordinates drawn (the rest of each ray's kDims left unset): an element link
    // needs only the point on its sender, not the other four.
    LatinHypercube(Rng& rng, int n, int dims = kDims) : n_(std::max(n, 1)) {
        thread_local std::vector<double> buf;  // one set in use per thread at a time
        buf.resize(size_t(n_) * kDims);
        u_ = buf.data();
        thread_local std::vector<int> perm;
        perm.resize(size_t(n_));
        for (int d = 0; d < dims; ++d) {
            for (int k = 0; k < n_; ++k) perm[size_t(k)] = k;
            for (int k = n_ - 1; k > 0; --k) std::swap(perm[size_t(k)], perm[size_t(std::min(k, int(rng.next() * (k + 1))))]);
            for (int k = 0; k < n_; ++k) u_[size_t(k) * kDims + d] = (perm[size_t(k)] + rng.next()) / n_;
        }
    }
    const double* at(int k) const { return u_ + size_t(k) * kDims; }

private:
    int n_;
    double* u_;
};

// Whether every vertex of `poly` lies more than `margin` in front of the plane (p, n): a
// receiver apart from its sender's plane, not touching it at a contact or crossing it.
bool in_front(const Poly& poly, const Vec3& p, const Vec3& n, double margin) {
    for (int k = 0; k < poly.n; ++k)
        if (dot(poly.v[size_t(k)] - p, n) <= margin) return false;
    return true;
}

// A kernel whose range over a receiver exceeds this share of its largest value is integrated
// densely (element_link).
constexpr double kSteepKernel = 0.25;
// An emitter's kernel that falls under this share of its largest value within the receiver:
// the emitter's outline crosses it (Link::outline).
constexpr double kOutline = 0.05;

// What the rays from one receiving point found of an element sender (element_link): the
// visibility v, kernel-weighted, and how many rays were clear of how many counted.
struct PointSight {
    double v = 1.0;
    int clear = 0, counted = 0;
};

// The visibility of sender P from receiving point p (normal n, the ray origin lifted off
// it), per_point rays stratified over P and weighted by the point-to-point kernel, as F
// (the unoccluded point form factor) is. With `record`, the leaves the clear rays reach join
// l.samples, each weighted by its share of w F (w the point's cubature weight).
template <class Vis>
PointSight element_point_sight(const Hierarchy& h, const Vis& vis, int p_id, const Vec3& p, const Vec3& n,
                               int per_point, uint64_t seed, double w, double F, bool record, Link& l) {
    const double lift = 1e-6 * h.scene_diag;  // keep ray ends off their own surfaces
    const Node& P = h.nodes[size_t(p_id)];
    thread_local std::vector<std::pair<Vec3, double>> hits;
    PointSight out;
    // Each point its own jitter stream: its rays do not depend on the points before it.
    Rng rng(seed);
    double wsum = 0, wclear = 0;
    Vec3 y = p + n * lift;
    // Rays go only to the part of the sender above the point's tangent plane, the
    // part F integrates over: drawn over the whole sender, every ray of a point could
    // land behind it (weight 0), and the point then counted as fully visible -- light
    // leaked into closed boxes from walls that straddle their planes.
    const FrontPart front = front_part(P.poly, p, n);
    const LatinHypercube strata(rng, per_point, 2);
    hits.clear();
    for (int r = 0; r < per_point; ++r) {
        // Stratified in both coordinates: fewer rays for the same variance.
        const double u1 = strata.at(r)[0], u2 = strata.at(r)[1];
        Vec3 x = (front.n ? front.sample(u1, u2) : P.poly.sample(u1, u2)) + P.normal * lift;
        // Visibility weighted by the point-to-point kernel, as F is: the sender's part
        // below the receiver's tangent plane (rays through the receiver's own object)
        // weighs nothing instead of counting as a shadow a second time (which would
        // darken a box's side under a ceiling light), and near parts weigh more.
        Vec3 yx = x - y;
        double d2 = length2(yx);
        double wr = d2 > 0 ? std::max(0.0, dot(yx, n)) * std::max(0.0, -dot(yx, P.normal)) / (d2 * d2) : 0.0;
        if (wr <= 0) continue;
        ++out.counted;
        wsum += wr;
        if (!vis.occluded(y, x)) {
            ++out.clear, wclear += wr;
            if (record) hits.push_back({x - P.normal * lift, wr});
        }
    }
    out.v = wsum > 0 ? wclear / wsum : 1.0;
    if (record) {
        if (wsum > 0)
            for (const auto& hx : hits) l.samples.push_back({h.leaf_at(p_id, hx.first), float(w * F * hx.second / wsum)});
        else
            l.samples.push_back({p_id, float(w * F)});  // no ray counted: v = 1 over the whole sender
    }
    return out;
}

// One ray from a receiver's point c (normal n) to a random point of the sender's part in
// front of it: whether it is clear.
template <class Vis>
bool corner_sees(const Hierarchy& h, const Vis& vis, const Node& P, const Vec3& c, const Vec3& n, Rng& rng) {
    const double lift = 1e-6 * h.scene_diag;
    const FrontPart front = front_part(P.poly, c, n);
    const double u1 = rng.next(), u2 = rng.next();
    const Vec3 x = (front.n ? front.sample(u1, u2) : P.poly.sample(u1, u2)) + P.normal * lift;
    return !vis.occluded(c + n * lift, x);
}

// The visible fraction of an element pair from `rays` rays between stratified points of the
// receiver Q and of the sender's part in front of each, weighted by the point-to-point kernel
// over the density they were drawn with; the clear rays' sender leaves go to the link's
// samples when `record` (their weights summing to K_unoccluded times the fraction).
template <class Vis>
double pair_sight(const Hierarchy& h, const Vis& vis, int src, const Node& Q, int rays, uint64_t seed, bool record,
                  Link& l) {
    const Node& P = h.nodes[size_t(src)];
    const double lift = 1e-6 * h.scene_diag;
    Rng rng(seed);
    const LatinHypercube strata(rng, rays, 4);
    thread_local std::vector<std::pair<Vec3, double>> hits;
    hits.clear();
    double wsum = 0, wclear = 0;
    for (int r = 0; r < rays; ++r) {
        const auto& u = strata.at(r);
        const Vec3 q = Q.poly.sample(u[0], u[1]);
        const FrontPart front = front_part(P.poly, q, Q.normal);
        if (front.n == 0) continue;
        const Vec3 x = front.sample(u[2], u[3]);
        const Vec3 d = x - q;
        const double d2 = length2(d);
        const double wr = d2 > 0 ? std::max(0.0, dot(d, Q.normal)) * std::max(0.0, -dot(d, P.normal)) / (d2 * d2) * front.area : 0.0;
        if (!(wr > 0)) continue;
        wsum += wr;
        if (!vis.occluded(q + Q.normal * lift, x + P.normal * lift)) {
            wclear += wr;
            if (record) hits.push_back({x, wr});
        }
    }
    const double v = wsum > 0 ? wclear / wsum : 0.0;
    for (const auto& hx : hits) l.samples.push_back({h.leaf_at(src, hx.first), float(l.K_unoccluded * hx.second / wsum)});
    return v;
}

// The range of a link's kernel over its receiver, unoccluded (f) and occluded (k).
struct KernelRange {
    double kmin = 1e300, kmax = -1e300;
    double fmin = 1e300, fmax = 0;
    void add(double F, double k) {
        fmin = std::min(fmin, F), fmax = std::max(fmax, F);
        kmin = std::min(kmin, k), kmax = std::max(kmax, k);
    }
};

// Where a receiver's corner disagreed with every one of its cubature rays: the visible
// fraction from rays between points drawn over the whole receiver and the sender, so that the
// link carries what the strip gets (or keeps out what it does not) even where the oracle keeps
// it; none clear, it stays (K = 0) for the oracle, whose kernel spread (the corner's) says
// whether to look closer. `cubature_clear`: every cubature ray was clear (the leaves they
// reached stay the link's samples, their weights now summing to K).
template <class Vis>
void remeasure_visibility(const Hierarchy& h, const Vis& vis, int src, const Node& Q, int rays, uint64_t seed,
                          bool record, bool cubature_clear, Link& l) {
    const double K_cubature = l.K;
    l.vis = pair_sight(h, vis, src, Q, rays, seed, record && !cubature_clear, l);
    l.K = l.K_unoccluded * l.vis;
    if (cubature_clear) {
        for (auto& sm : l.samples) sm.second = float(double(sm.second) * (K_cubature > 0 ? l.K / K_cubature : 0.0));
        if (!(l.K > 0)) l.samples.clear();
    }
    l.blocked = !(l.K > 0);
}

template <class Vis>
Link element_link(const Hierarchy& h, const Vis& vis, int src, const Node& Q, int rays, uint64_t seed) {
    const Node& P = h.nodes[size_t(src)];
    Link l;
    const double eps = 1e-7 * h.scene_diag;
    if (P.pocket != Q.pocket) return l;  // closed pockets (Pockets::compute): nothing gets in or out
    if (!can_face(P.poly, P.normal, Q.poly, Q.normal, eps)) return l;
    Cubature cub = receiver_cubature(Q.poly, P.poly.v[0], P.normal);
    const int per_point = std::max(1, rays / cub.n);
    KernelRange r;
    bool any_blocked = false, any_clear = false;
    // A subdivided sender: its radiance toward Q is that of the leaves its clear rays reach,
    // not its area average (see Link::samples).
    const bool record = !P.children.empty();
    for (int j = 0; j < cub.n; ++j) {
        double F = point_polygon_form_factor(cub.p[j], Q.normal, P.poly, P.normal);
        double v = 1.0;
        if (F > 0) {
            const PointSight ps = element_point_sight(h, vis, src, cub.p[j], Q.normal, per_point,
                                                      Hierarchy::mix(seed, uint64_t(j + 1)), cub.w[j], F, record, l);
            v = ps.v;
            if (ps.clear < ps.counted) any_blocked = true;
            if (ps.clear > 0 || ps.counted == 0) any_clear = true;
        }
        const double k = F * v;
        r.add(F, k);
        l.K_unoccluded += cub.w[j] * F;
        l.K += cub.w[j] * k;
    }
    l.vis = l.K_unoccluded > 0 ? l.K / l.K_unoccluded : 0.0;
    // The kernel at the corners too: symmetric cubature points can see equal values where
    // the kernel varies (a receiver centred under its sender). Corners get the mean
    // visibility, the cubature points their own -- but where the cubature rays all agree
    // (every one blocked, or every one clear), each corner casts one ray of its own: a strip
    // along the receiver's edge outside its cubature points, lit (a wall's top centimetres
    // above a cabinet, the rest of the element in the gap behind it) or in shadow (a floor's
    // edge under a sofa), is otherwise missed by every ray, and the link dropped as occluded
    // or taken as clear.
    const bool agree = l.K_unoccluded > 0 && any_blocked != any_clear;
    bool varies = false;
    Rng corner_rng(Hierarchy::mix(seed, 0xc0e7u));
    for (int k = 0; k < Q.poly.n; ++k) {
        Vec3 c = Q.poly.v[k] * 0.999 + Q.center * 0.001;  // just inside: kernels of neighbours meeting at an edge are singular there
        const double F = point_polygon_form_factor(c, Q.normal, P.poly, P.normal);
        double v = l.vis;
        if (agree && F > 0) {
            const bool seen = corner_sees(h, vis, P, c, Q.normal, corner_rng);
            if (seen != any_clear) v = seen ? 1.0 : 0.0, varies = true;
        }
        r.add(F, F * v);
    }
    if (varies) {
        remeasure_visibility(h, vis, src, Q, rays, Hierarchy::mix(seed, 0x5717u), record, any_clear, l);
        any_blocked = any_clear = true;
    }
    l.partial = any_blocked && any_clear;
    // An emitter's kernel that steps within a receiver apart from it (its outline close over
    // the receiver, as a lamp just under a ceiling): four Gauss points read a step too high or
    // too low, and the oracle may keep the link (the receiver at the area floor), so the bias
    // adds up over the outline. The unoccluded coupling from 64 points instead, the
    // visibility the rays measured kept. Emitters only: a reflector's light reaches the
    // output through the final gather's own point couplings, and where the receiver touches
    // the sender's plane (a contact) those rely on the solution's.
    const bool emits = P.emission.max() > 0;
    l.outline = emits && r.fmax > 0 && r.fmin <= kOutline * r.fmax;
    if (emits && r.fmax > 0 && r.fmax - r.fmin > kSteepKernel * r.fmax && l.K_unoccluded > 0 &&
        in_front(Q.poly, P.poly.v[0], P.normal, 1e-3 * std::sqrt(Q.area))) {
        const double dense = unoccluded_coupling(Q.poly, Q.normal, P, 2);
        l.K *= dense / l.K_unoccluded;
        l.K_unoccluded = dense;
    }
    // The spread of the occluded kernel over the receiver: in a penumbra it includes the
    // change of visibility across the receiver, so shadow boundaries refine.
    l.dK = r.kmax - r.kmin;
    return l;
}

// The surface_order position in [begin, end) whose area covers x in Hierarchy::area_prefix
// (x from area_prefix[begin] up): a cluster's surfaces drawn by area in O(log n).
int surface_at_area(const Hierarchy& h, int begin, int end, double x) {
    const double* pre = h.area_prefix.data();
    const int i = int(std::upper_bound(pre + begin + 1, pre + end + 1, x) - (pre + 1));
    return std::min(std::max(i, begin), end - 1);
}

// Picks surfaces of a node in proportion to their projected area toward d: the surfaces
// that can take part in a transfer along d are the ones worth a ray. A cluster's surfaces
// come from the contiguous Hierarchy::surface_geom range; the buffers are the thread's own
// (a link evaluation is too short for two allocations each).
//
// `min_cos` floors the density's cosine for the surfaces that face d at all: area x
// max(cos, min_cos) (final gather). The cosine toward d stands for the cosine toward the
// point, which for a surface nearly edge-on to d can be many times larger (the point lies off
// the centre's axis); drawn by cos alone such a surface would get a tiny density and, when a
// ray landed on it, a huge weight (and the point's closure would then scale its other links
// down to make its couplings sum to 1). Surfaces facing away from d are still left out:
// drawing them as well (density area x max(0, cos + 2 R / r), which bounds every weight)
// costs more in variance than they bring (docs/decisions.md, "Output").
class FacingSampler {
public:
    struct Buffers {
        std::vector<int> ids;
        std::vector<double> cdf;
    };
    // Only surfaces in a pocket the other end has surfaces in take part: the rest cannot see it
    // (the inside of a closed crate, seen from the room).
    FacingSampler(const Hierarchy& h, int node, const Vec3& d, int other, Buffers& buf, double min_cos = 0.0)
        : h_(h), ids_(buf.ids), cdf_(buf.cdf), min_cos_(min_cos) {
        ids_.clear();
        cdf_.clear();
        const Node& n = h.nodes[node];
        auto take = [&h, other](int pocket) { return h.holds_pocket(other, pocket); };
        if (!n.is_cluster()) {
            single_ = {n.poly, n.normal, n.area, n.poly.first_share(), node, n.object, n.pocket};
            if (take(n.pocket)) add(-1, n.area * weight(dot(n.normal, d)));
            total_ = cdf_.empty() ? 0.0 : cdf_.back();
            return;
        }
        if (h.has_facing_summary(node)) {
            // A large cluster of few normals in one pocket: the projected area is a sum over
            // its normals, and surfaces are drawn by area and kept with probability cos over
            // the largest cos of its normals (rejection: a floor seen edge-on keeps each draw
            // that faces d, not one in ten), unless so little of it faces d that rejection
            // would spin.
            const Hierarchy::FacingSummary& f = h.facing_summary[size_t(node)];
            double facing = 0;
            for (const auto& grp : f.groups)
                if (take(grp.pocket)) {
                    const double c = weight(dot(grp.normal, d));
                    facing += grp.area * c;
                    c_max_ = std::max(c_max_, c);
                }
            const double area = h.area_prefix[size_t(n.surf_end)] - h.area_prefix[size_t(n.surf_begin)];
            if (facing <= 0 || facing >= area / 64) {
                summary_ = true;
                total_ = facing;
                begin_ = n.surf_begin;
                end_ = n.surf_end;
                d_ = d;
                other_ = other;
                return;
            }
        }
        for (int i = n.surf_begin; i < n.surf_end; ++i) {
            const SurfaceGeom& g = h.surface_geom[i];
            if (take(g.pocket)) add(i, g.area * weight(dot(g.normal, d)));
        }
        total_ = cdf_.empty() ? 0.0 : cdf_.back();
    }
    double total() const { return total_; }
    // The density's weight per area of a surface whose normal has this cosine toward d.
    double weight(double cos_d) const { return cos_d > 0 ? std::max(cos_d, min_cos_) : 0.0; }
    // A point on a chosen surface, its normal and the surface root. u: the stratified
    // numbers of this ray (pick, then the point on the surface); rejection's further tries
    // and its acceptance draws come from rng.
    Vec3 sample(Rng& rng, const double* u, Vec3* normal, int* root) const {
        const SurfaceGeom* pick = nullptr;
        if (summary_) {
            const double* pre = h_.area_prefix.data();
            const double lo = pre[begin_], span = pre[end_] - lo;
            for (int tries = 0; tries < 4096; ++tries) {
                const double x = lo + (tries == 0 ? u[0] : rng.next()) * span;
                const SurfaceGeom& g = h_.surface_geom[size_t(surface_at_area(h_, begin_, end_, x))];
                const double c = weight(dot(g.normal, d_));
                if (c <= 0 || !h_.holds_pocket(other_, g.pocket)) continue;
                pick = &g;  // after 4096 tries: the last taking part
                if (c >= c_max_ || rng.next() * c_max_ < c) break;
            }
            if (!pick) pick = &h_.surface_geom[size_t(begin_)];
        } else {
            const double x = u[0] * total();
            size_t i = size_t(std::upper_bound(cdf_.begin(), cdf_.end(), x) - cdf_.begin());
            i = std::min(i, ids_.size() - 1);
            pick = ids_[i] < 0 ? &single_ : &h_.surface_geom[ids_[i]];
        }
        const SurfaceGeom& g = *pick;
        *normal = g.normal;
        *root = g.root;
        return g.poly.sample(g.share, u[1], u[2]);
    }

private:
    void add(int i, double w) {
        if (w <= 0) return;
        ids_.push_back(i);
        cdf_.push_back((cdf_.empty() ? 0.0 : cdf_.back()) + w);
    }
    const Hierarchy& h_;
    std::vector<int>& ids_;
    std::vector<double>& cdf_;
    SurfaceGeom single_;  // an element end
    double total_ = 0;
    double min_cos_ = 0;
    bool summary_ = false;  // sampling by rejection over [begin_, end_)
    double c_max_ = 0;      // ... keeping a draw with probability weight / c_max_
    int begin_ = 0, end_ = 0, other_ = -1;
    Vec3 d_;
};

// Draws a surface of a large cluster for a point transfer by descending the cluster's tree:
// each child is taken in proportion to its weight toward d, an upper bound of its projected
// area read from its axis bins plus min_cos times its area (FacingSampler's floor), so a draw
// costs O(depth) where FacingSampler's table over every surface costs O(surfaces) to build,
// for every point that reads the cluster. The bound sum_a |d_a| max(0, +-n_a) >= cos is
// additive over children, so the probability of a surface is its own weight over the
// cluster's; surfaces facing away keep the floor (wasted draws, no bias).
class TreeSampler {
public:
    // Each cluster's children's weights toward d, made at the first draw that reaches it and
    // read by the transfer's later draws (they share d: every ray of a transfer passes the top
    // levels). The thread's own buffers, reused from transfer to transfer.
    struct Memo {
        std::vector<int> node;           // open addressing by node id (-1: empty)
        std::vector<uint32_t> at;        // ... where its weights start in `weights`
        std::vector<double> total;       // ... and their sum
        std::vector<int> used;           // slots filled by this transfer (cleared at the next)
        std::vector<double> weights;
    };
    TreeSampler(const Hierarchy& h, int node, const Vec3& d, double min_cos, Memo& memo)
        : h_(h), node_(node), d_(d), min_cos_(min_cos), memo_(memo) {
        if (memo_.node.empty()) {
            memo_.node.assign(kSlots, -1);
            memo_.at.assign(kSlots, 0);
            memo_.total.assign(kSlots, 0.0);
        }
        for (int k : memo_.used) memo_.node[size_t(k)] = -1;
        memo_.used.clear();
        memo_.weights.clear();
    }

    // A record's weight toward d, from the samplers' copy of the cluster tree.
    double weight(const Hierarchy::SamplerRecord& n) const {
        if (n.dead || !(n.area > 0)) return 0.0;
        double b = 0;
        if (n.cluster) {
            for (int a = 0; a < 3; ++a) b += std::fabs(d_[a]) * n.W[size_t(bin_of(a, d_[a]))];
            return b + min_cos_ * n.area;
        }
        for (int a = 0; a < 3; ++a) b += std::fabs(d_[a]) * std::max(0.0, (d_[a] < 0 ? -1.0 : 1.0) * n.W[size_t(a)]);
        return n.area * (b + min_cos_);
    }
    // A surface root, drawn by u in [0, 1) (rescaled at each level, so strata carry down), and
    // the probability of drawing it; nullptr when the cluster has nothing to draw.
    const Hierarchy::SamplerRecord* draw(double u, double* prob) const {
        int id = node_;
        double p = 1.0;
        const Hierarchy::SamplerRecord* got = nullptr;
        // (Below the top, a cluster's range is read from its own record: one read a level.)
        int first = h_.sampler_first[size_t(id)], m = h_.sampler_first[size_t(id) + 1] - first;
        for (bool cluster = h_.nodes[size_t(id)].is_cluster(); cluster;) {
            const Hierarchy::SamplerRecord* ch = h_.sampler_records.data() + first;
            double total = 0;
            const double* ws = weights_of(id, ch, m, total);
            if (!(total > 0)) return nullptr;
            double x = u * total, acc = 0;
            int pick = -1;
            double w_pick = 0;
            for (int i = 0; i < m; ++i) {
                const double w = ws[size_t(i)];
                if (w <= 0) continue;
                pick = i, w_pick = w;
                if (x < acc + w) break;
                acc += w;
            }
            u = std::min(std::max((x - acc) / w_pick, 0.0), std::nextafter(1.0, 0.0));
            p *= w_pick / total;
            got = &ch[pick];
            id = got->id;
            cluster = got->cluster;
            first = got->first, m = got->count;
        }
        *prob = p;
        return got;
    }

private:
    static constexpr size_t kSlots = 1024;  // a power of two; filled to half at most
    // Cluster id's children's weights (m of them from ch) and their sum, from the memo or
    // made now (and kept while the memo has room).
    const double* weights_of(int id, const Hierarchy::SamplerRecord* ch, int m, double& total) const {
        size_t k = (uint32_t(id) * 2654435761u) & (kSlots - 1);
        while (memo_.node[k] >= 0 && memo_.node[k] != id) k = (k + 1) & (kSlots - 1);
        if (memo_.node[k] == id) {
            total = memo_.total[k];
            return memo_.weights.data() + memo_.at[k];
        }
        const size_t at = memo_.weights.size();
        total = 0;
        for (int i = 0; i < m; ++i) {
            memo_.weights.push_back(weight(ch[i]));
            total += memo_.weights.back();
        }
        if (memo_.used.size() < kSlots / 2) {
            memo_.node[k] = id;
            memo_.at[k] = uint32_t(at);
            memo_.total[k] = total;
            memo_.used.push_back(int(k));
        }
        return memo_.weights.data() + at;
    }
    const Hierarchy& h_;
    int node_;
    Vec3 d_;
    double min_cos_;
    Memo& memo_;
};

// Whether every surface below P and Q lies in one plane (either side of it), to within its
// own warp (a quad is planar only to 1e-4 of its size: one of Bevel's or a float32 vertex's
// rounding). Stops at the first surface off the plane, so mixed clusters cost little.
bool coplanar(const Hierarchy& h, const Node& P, const Node& Q) {
    const double tol = 1e-9 * h.scene_diag;  // far above the 2^-36 snapping of the input
    Vec3 n0;
    double d0 = 0, w0 = 0;
    bool have = false;
    auto on_plane = [&](const Poly& poly, const Vec3& normal) {
        const double w = warp(poly, normal);
        if (!have) {
            n0 = normal;
            d0 = dot(n0, poly.v[0]);
            w0 = w;
            have = length2(n0) > 0;
            if (!have) return false;
        }
        if (std::fabs(std::fabs(dot(normal, n0)) - 1.0) > 1e-8) return false;
        for (int k = 0; k < poly.n; ++k)
            if (std::fabs(dot(n0, poly.v[k]) - d0) > tol + 2 * w0 + 2 * w) return false;
        return true;
    };
    for (const Node* c : {&P, &Q}) {
        if (!c->is_cluster()) {
            if (!on_plane(c->poly, c->normal)) return false;
            continue;
        }
        for (int i = c->surf_begin; i < c->surf_end; ++i)
            if (!on_plane(h.surface_geom[i].poly, h.surface_geom[i].normal)) return false;
    }
    return have;
}

// Whether some surface of node n in a pocket of node `other` faces direction d within a cone
// of sine s.
bool may_face(const Hierarchy& h, const Node& n, const Vec3& d, double s, int other) {
    if (!n.is_cluster()) return dot(n.normal, d) > -s;
    for (int i = n.surf_begin; i < n.surf_end; ++i) {
        const SurfaceGeom& g = h.surface_geom[i];
        if (dot(g.normal, d) > -s && h.holds_pocket(other, g.pocket)) return true;
    }
    return false;
}

// Whether some surface below n has part of `box` strictly in front of its plane: a
// necessary condition for n to send light into the box (or receive light from it).
bool faces_box(const Hierarchy& h, const Node& n, const Aabb& box, double eps) {
    auto front = [&](const Poly& poly, const Vec3& normal) { return plane_reach(box, poly.v[0], normal) > eps; };
    if (!n.is_cluster()) return front(n.poly, n.normal);
    for (int i = n.surf_begin; i < n.surf_end; ++i)
        if (front(h.surface_geom[i].poly, h.surface_geom[i].normal)) return true;
    return false;
}

// Whether the two ends can exchange light at all: each has a surface with part of the
// other in front of it. Checked before a link whose point model fails is refined: without
// it a floor element and a far cluster of floor pieces in its plane (their centres "do not
// face", yet each piece faces within the cluster's angular size) refined into every pair of
// floor elements, each then dropped as coplanar.
bool may_exchange(const Hierarchy& h, const Node& P, const Node& Q) {
    const double eps = 1e-7 * h.scene_diag;
    return faces_box(h, P, Q.box, eps) && faces_box(h, Q, P.box, eps);
}

}  // namespace

// coupling_bound (transfer.h): at distance at least d, a surface of P whose plane Q's box
// rises at most h over sends under a cosine of h / d, and a receiving element over whose plane
// P's box rises at most h' takes under h' / d. Two ends that stand well apart and see each
// other at grazing angles (a wall and what stands a few centimetres before it) get a small
// bound.
double coupling_bound(const Hierarchy& h, int src, int rcv) {
    const Node& P = h.nodes[size_t(src)];
    const Node& Q = h.nodes[size_t(rcv)];
    const double d2 = P.box.distance2(Q.box);
    const double d = std::sqrt(d2);
    if (!(d > 1e-9 * h.scene_diag)) return 1.0;
    auto sends = [&](const Poly& poly, const Vec3& normal, double area) {
        return area * std::min(1.0, std::max(0.0, plane_reach(Q.box, poly.v[0], normal)) / d);
    };
    double sum = 0;
    if (!P.is_cluster()) sum = sends(P.poly, P.normal, P.area);
    else
        for (int i = P.surf_begin; i < P.surf_end; ++i) {
            const SurfaceGeom& g = h.surface_geom[size_t(i)];
            sum += sends(g.poly, g.normal, g.area);
        }
    const double takes = Q.is_cluster() ? 1.0 : std::min(1.0, std::max(0.0, plane_reach(P.box, Q.poly.v[0], Q.normal)) / d);
    return std::min(1.0, sum * takes / (kPi * d2));
}

namespace {

// What a cluster link's pairs of points found (cluster_link): the kernel-weighted sums over
// the pairs (wsum), over the clear ones (vsum) and over those whose receiving point its own
// object hides (wself), and how many pairs were clear of how many cast.
struct PairSight {
    double wsum = 0, vsum = 0;
    int clear = 0, cast = 0;
    double wself = 0;
};

// Casts the rays of a cluster link from P to Q along l.dir: pairs of points drawn by the
// samplers ps (of P) and qs (of Q), each weighted by the point-to-point kernel over the
// samplers' density. A sending cluster's clear rays add the leaves they reach to l.samples.
template <class Vis>
PairSight cluster_pair_sight(const Hierarchy& h, const Vis& vis, const Node& P, const Node& Q, const FacingSampler& ps,
                             const FacingSampler& qs, int rays, Rng& rng, Link& l) {
    PairSight s;
    const double lift = 1e-6 * h.scene_diag;
    const LatinHypercube strata(rng, rays);
    for (int k = 0; k < rays; ++k) {
        Vec3 nx, ny;
        int sroot = -1, rroot = -1;
        Vec3 x = ps.sample(rng, strata.at(k), &nx, &sroot);
        Vec3 y = qs.sample(rng, strata.at(k) + 3, &ny, &rroot);
        Vec3 xy = y - x;
        double d2 = length2(xy);
        if (d2 <= 0) continue;
        double w = std::max(0.0, dot(nx, xy)) * std::max(0.0, -dot(ny, xy)) / (d2 * d2);
        double pdf = dot(nx, l.dir) * -dot(ny, l.dir);  // > 0 by construction
        w /= pdf;
        ++s.cast;
        if (w <= 0) continue;
        bool ok = !vis.occluded(x + nx * lift, y + ny * lift);
        // A receiving point hidden by its own object (the inner faces of a closed two-sided
        // box, or of one open at the bottom standing on the floor, share the room's pocket):
        // the gather shares K by cosine over the receiver's surfaces facing the sender, so
        // the visibility that K carries must be that of the surfaces that can be lit at all.
        // Counted as blocked, such points would cut what every outer face of a box gets.
        if (!ok && Q.is_cluster() && rroot >= 0 &&
            vis.hidden_by(y + ny * lift, x + nx * lift, lift, h.nodes[size_t(rroot)].object))
            s.wself += w;
        if (ok && P.is_cluster()) l.samples.push_back({h.leaf_at(sroot, x), float(w)});
        s.wsum += w;
        s.vsum += ok ? w : 0.0;
        s.clear += ok;
    }
    return s;
}

template <class Vis>
Link cluster_link(const Hierarchy& h, const Vis& vis, const Node& P, const Node& Q, int rays, Rng& rng,
                  int src, int rcv) {
    Link l;
    l.cluster = true;
    // No pocket has surfaces at both ends: no light passes, at any level below either (the
    // room and the inside of a closed crate in it). Not even worth a refinement.
    if (!h.share_pocket(src, rcv)) return l;
    Vec3 d = Q.center - P.center;
    double r = length(d);
    l.dist = r;
    if (r <= P.radius + Q.radius || r <= 1e-9 * h.scene_diag) {
        // Surfaces in one plane exchange no light (the element kernel is 0 for them), so
        // there is nothing to refine toward. Without this, a fan-split n-gon (every piece
        // touches the apex, so every pair of its sub-clusters overlaps) or a finely
        // triangulated floor refined into all element pairs: O(n^2) links evaluated.
        if (coplanar(h, P, Q) || !may_exchange(h, P, Q)) return l;
        // The point model is meaningless for overlapping bounding spheres: refine first.
        l.must_refine = true;
        l.K_bound = float(coupling_bound(h, src, rcv));
        l.dir = r > 0 ? d / r : Vec3{0, 0, 1};
        l.K = l.K_unoccluded = 0;
        return l;
    }
    l.dir = d / r;
    thread_local FacingSampler::Buffers buf[2];
    FacingSampler ps(h, src, l.dir, rcv, buf[0]), qs(h, rcv, -l.dir, src, buf[1]);
    const double pa = ps.total();
    double rcv_cos = Q.is_cluster() ? 1.0 : std::max(0.0, dot(Q.normal, -l.dir));
    l.K_unoccluded = pa * rcv_cos / (kPi * r * r);
    if (l.K_unoccluded <= 0 || qs.total() <= 0) {
        l.K_unoccluded = 0;
        // The centre-to-centre direction says the ends do not face each other, but an
        // extended end can still be seen in part (the side of a box standing under a ceiling
        // light sees only the part of the light in front of it: dropping the link would leave
        // it dark). When some surface of each end faces within the ends' angular size, refine
        // until the exact element kernel decides.
        const double s = std::min(1.0, (P.radius + Q.radius) / r);
        if (may_face(h, P, l.dir, s, rcv) && may_face(h, Q, -l.dir, s, src) && may_exchange(h, P, Q)) {
            l.must_refine = true;
            l.K_bound = float(coupling_bound(h, src, rcv));
        }
        return l;
    }
    // Visibility of the transfer, estimated with pairs of points drawn by projected area
    // toward each other and weighted by the true point-to-point kernel over that density.
    PairSight ray = cluster_pair_sight(h, vis, P, Q, ps, qs, rays, rng, l);
    if (ray.clear == 0 && ray.cast > 0 && (P.emission.max() > 0 || h.emits(src, Hierarchy::Unknown::Dark))) {
        // Every ray from an emitter blocked: a second batch before the link is taken as
        // hidden. A part seen by a tenth of the pairs (a wall's strip above a cabinet beside
        // it) escapes one batch of 16 rays one time in five, and the oracle, which may keep a
        // blocked link, then drops a lamp's light there. Emitters only: why, in
        // docs/decisions.md ("Visibility").
        const PairSight more = cluster_pair_sight(h, vis, P, Q, ps, qs, rays, rng, l);
        ray.wsum += more.wsum, ray.vsum += more.vsum, ray.wself += more.wself;
        ray.clear += more.clear, ray.cast += more.cast;
    }
    l.vis = ray.wsum > 0 ? ray.vsum / ray.wsum : 0.0;
    l.partial = ray.clear > 0 && ray.clear < ray.cast;
    // Every ray blocked is weak evidence for a whole cluster: the link stays (K = 0) and the
    // oracle decides from the light at stake whether to look closer. Splitting every such
    // link unconditionally goes down to element pairs, most of them facing away or hidden
    // (under and behind furniture).
    l.blocked = ray.clear == 0 && ray.cast > 0;
    // vis, partial and blocked keep every point (the oracle still sees the link as partly
    // occluded and splits the receiver when the light at stake asks for it); the coupling
    // leaves out the points their own object hides.
    l.K = ray.wsum > ray.wself ? l.K_unoccluded * ray.vsum / (ray.wsum - ray.wself) : 0.0;
    return l;
}

// Samples (those from `first` on) that name the same leaf become one, with their weights
// summed, in the order of their first appearance: a sender's radiance is the same weighted
// mean, and fewer samples are stored, copied into each gather plan and read in each sweep (a
// link's rays often land on the same leaf).
void merge_samples(std::vector<std::pair<int, float>>& s, size_t first = 0) {
    size_t n = first;
    for (size_t i = first; i < s.size(); ++i) {
        size_t j = first;
        while (j < n && s[j].first != s[i].first) ++j;
        if (j < n) s[j].second += s[i].second;
        else s[n++] = s[i];
    }
    s.resize(n);
}

template <class Vis>
Link evaluate_with(const Hierarchy& h, const Vis& vis, int src, int rcv, int rays, uint64_t seed) {
    const Node& P = h.nodes[src];
    const Node& Q = h.nodes[rcv];
    Rng rng(seed);
    Link l;
    if (!P.is_cluster() && !Q.is_cluster()) {
        l = element_link(h, vis, src, Q, rays, seed);
        Vec3 d = Q.center - P.center;
        l.dist = length(d);
        l.dir = l.dist > 0 ? d / l.dist : P.normal;
    } else {
        l = cluster_link(h, vis, P, Q, rays, rng, src, rcv);
    }
    merge_samples(l.samples);
    l.src = src;
    l.rcv = rcv;
    return l;
}

// Point transfers (point_transfer_with): a cluster of more children than this, with the
// point near it, has its surfaces drawn by area.
constexpr size_t kDescendChildren = 16;
// A cluster of at most this many surfaces sends as its surfaces, each an element sender.
constexpr int kExactClusterSurfaces = 12;
constexpr double kGatherMinCos = 0.1;  // FacingSampler's min_cos
// inv_dist leaves out surfaces turned less than 60 degrees from the point's own (the
// faces beyond a gentle concave bend of a curved mesh, met a hair away): the light they
// bring changes slowly along the surface, not over their distance.
constexpr double kGentle = 0.5;
// Beyond this many surfaces (and without a facing summary) a cluster is drawn down its tree.
constexpr int kTreeSampleSurfaces = 256;

// The rays of one point transfer from x (normal n): cast from y, x lifted off its surface,
// `rays` of them; what they find adds to t, and the leaves the clear ones reach (with their
// weights) to `samples`.
struct PointRays {
    const Hierarchy& h;
    PointRayStream& vis;
    const Vec3& x;
    const Vec3& n;
    Vec3 y;
    double lift;
    int rays;
    Rng rng;
    PointTransfer& t;
    std::vector<std::pair<int, float>>& samples;
    int clear_draws = 0;  // tally's rays that were clear

    // One ray of a sender drawn by density den / num per area (a cluster's samplers): the
    // point kernel cos cos / (pi r^2) over that density, toward s (normal ns) on surface root
    // `root`; the clear ones keep their leaf for the sender's radiance.
    void tally(const Vec3& s, const Vec3& ns, int root, double num, double den) {
        const Vec3 yx = s - y;
        const double d2 = length2(yx);
        if (d2 <= 0) return;
        const double g = std::max(0.0, dot(yx, n)) * std::max(0.0, -dot(yx, ns)) / (d2 * d2) * num / (kPi * den * rays);
        if (g <= 0) return;
        ++t.cast;
        t.F_unoccluded += g;
        if (!vis.occluded(y, s + ns * lift)) {
            ++clear_draws;
            t.F += g;
            if (dot(n, ns) < kGentle) t.inv_dist += g / std::sqrt(d2);
            samples.push_back({h.leaf_at(root, s), float(g)});
        }
    }
    // Some of tally's rays were blocked and some clear.
    bool partial() const { return clear_draws > 0 && clear_draws < t.cast; }
};

// An element sender (node src, in `pocket` or no light passes): as element_link does for one
// cubature point, rays only to the part of the sender in front of the point's tangent plane,
// weighted by the point-to-point kernel.
void element_transfer(PointRays& pr, int src, int pocket) {
    const Hierarchy& h = pr.h;
    const Node& P = h.nodes[size_t(src)];
    const Vec3& n = pr.n;
    PointTransfer& t = pr.t;
    if (P.pocket != pocket) return;
    const double F = point_polygon_form_factor(pr.x, n, P.poly, P.normal);
    if (!(F > 0)) return;
    t.F_unoccluded = F;
    const FrontPart front = front_part(P.poly, pr.x, n);
    const LatinHypercube strata(pr.rng, pr.rays, 2);
    thread_local std::vector<std::pair<int, double>> hits;
    hits.clear();
    double wsum = 0, wclear = 0, winv = 0;
    int clear = 0, counted = 0;
    for (int r = 0; r < pr.rays; ++r) {
        const double u1 = strata.at(r)[0], u2 = strata.at(r)[1];
        const Vec3 s = front.n ? front.sample(u1, u2) : P.poly.sample(u1, u2);
        const Vec3 yx = s - pr.y;
        const double d2 = length2(yx);
        const double w = d2 > 0 ? std::max(0.0, dot(yx, n)) * std::max(0.0, -dot(yx, P.normal)) / (d2 * d2) : 0.0;
        if (w <= 0) continue;
        ++counted;
        ++t.cast;
        wsum += w;
        if (!pr.vis.occluded(pr.y, s + P.normal * pr.lift)) {
            ++clear;
            wclear += w;
            if (dot(n, P.normal) < kGentle) winv += w / std::sqrt(d2);
            hits.push_back({P.children.empty() ? src : h.leaf_at(src, s), w});
        }
    }
    t.partial = clear > 0 && clear < counted;
    if (wsum <= 0) {
        pr.samples.push_back({src, float(F)});  // no ray counted: the whole sender, unoccluded
        t.F = F;
    } else {
        for (const auto& hx : hits) pr.samples.push_back({hx.first, float(F * hx.second / wsum)});
        t.F = F * wclear / wsum;
        t.inv_dist = F * winv / wsum;
    }
}

// Near a cluster of many children (the pieces of a fanned n-gon hang side by side): its
// surfaces (those in `pocket`) drawn uniformly by area instead, each weighted by the true
// kernel, unbiased whichever way they face, and bounded in cost.
void draw_by_area(PointRays& pr, const Node& P, int pocket) {
    const Hierarchy& h = pr.h;
    const double* pre = h.area_prefix.data();
    const double lo = pre[P.surf_begin], span = pre[P.surf_end] - lo;
    if (!(span > 0)) return;
    const LatinHypercube strata(pr.rng, pr.rays, 3);
    for (int k = 0; k < pr.rays; ++k) {
        const double* u = strata.at(k);
        const SurfaceGeom& g = h.surface_geom[size_t(surface_at_area(h, P.surf_begin, P.surf_end, lo + u[0] * span))];
        if (g.pocket != pocket || h.nodes[size_t(g.root)].dead) continue;
        pr.tally(g.poly.sample(g.share, u[1], u[2]), g.normal, g.root, span, 1.0);
    }
    pr.t.partial = pr.partial();
}

// A cluster (node src) away from the point: its surfaces drawn by their facing toward the
// direction from its centre to the point, those in `pocket` (the receiving leaf rcv_leaf's).
void draw_far_cluster(PointRays& pr, int src, int rcv_leaf, int pocket) {
    const Hierarchy& h = pr.h;
    const Node& P = h.nodes[size_t(src)];
    Vec3 d = pr.x - P.center;
    const double r0 = length(d);
    if (!(r0 > 1e-9 * h.scene_diag)) return;
    d = d / r0;
    const LatinHypercube strata(pr.rng, pr.rays, 3);
    if (P.surf_end - P.surf_begin > kTreeSampleSurfaces && !h.has_facing_summary(src)) {
        // A large cluster of many normals (a bevelled, subdivided sofa): drawn down its
        // tree, the density the surface's probability over its area.
        thread_local TreeSampler::Memo memo;
        const TreeSampler tree(h, src, d, kGatherMinCos, memo);
        for (int k = 0; k < pr.rays; ++k) {
            const double* u = strata.at(k);
            double prob = 0;
            const Hierarchy::SamplerRecord* c = tree.draw(u[0], &prob);
            if (!c) break;
            if (c->pocket != pocket || !(prob > 0)) continue;
            const SurfaceGeom& g = h.surface_geom[size_t(c->geom)];
            pr.tally(g.poly.sample(g.share, u[1], u[2]), g.normal, c->id, g.area, prob);
        }
    } else {
        thread_local FacingSampler::Buffers buf;
        FacingSampler ps(h, src, d, rcv_leaf, buf, kGatherMinCos);
        const double total = ps.total();
        if (!(total > 0)) return;
        for (int k = 0; k < pr.rays; ++k) {
            Vec3 ny;
            int sroot = -1;
            const Vec3 s = ps.sample(pr.rng, strata.at(k), &ny, &sroot);
            const double pdf = ps.weight(dot(ny, d));  // the sampler's density over area, times total
            if (pdf <= 0) continue;
            pr.tally(s, ny, sroot, total, pdf);
        }
    }
    pr.t.partial = pr.partial();
}

PointTransfer point_transfer_with(const Hierarchy& h, PointRayStream& vis, int src, const Vec3& x, const Vec3& n,
                                  int rcv_leaf, int rays, uint64_t seed, std::vector<std::pair<int, float>>& samples) {
    PointTransfer t;
    const Node& P = h.nodes[size_t(src)];
    const Node& R = h.nodes[size_t(rcv_leaf)];
    const double lift = 1e-6 * h.scene_diag;
    rays = std::max(rays, 1);
    PointRays pr{h, vis, x, n, x + n * lift, lift, rays, Rng(seed), t, samples};
    const size_t first = samples.size();
    if (!P.is_cluster()) {
        element_transfer(pr, src, R.pocket);
    } else if (length(x - P.center) < 2.0 * P.radius && P.children.size() > kDescendChildren) {
        draw_by_area(pr, P, R.pocket);
    } else if (length(x - P.center) < 2.0 * P.radius) {
        // The point is near the cluster, or inside it (a floor point and the room around it):
        // no single direction says which of its surfaces face the point, and drawing them by
        // their facing toward the cluster's centre would miss the floor beside a block's
        // foot. Its children are asked instead, down to surfaces near the point, the rays
        // shared by area.
        PointTransfer sum;
        for (int c : P.children) {
            const Node& C = h.nodes[size_t(c)];
            if (C.dead || !(C.area > 0)) continue;
            const int r = std::max(1, int(std::lround(rays * C.area / P.area)));
            sum += point_transfer_with(h, vis, c, x, n, rcv_leaf, r, Hierarchy::mix(seed, C.key), samples);
        }
        return sum;
    } else if (P.surf_end - P.surf_begin <= kExactClusterSurfaces) {
        // A cluster of a few surfaces (a lamp's quad, a box): each one exactly, as an element
        // sender, the rays shared among them. Drawn by area they cost variance for nothing.
        const int m = P.surf_end - P.surf_begin;
        PointTransfer sum;
        for (int i = P.surf_begin; i < P.surf_end; ++i) {
            const SurfaceGeom& g = h.surface_geom[size_t(i)];
            if (g.pocket != R.pocket || h.nodes[size_t(g.root)].dead) continue;
            sum += point_transfer_with(h, vis, g.root, x, n, rcv_leaf, std::max(1, rays / m), Hierarchy::mix(seed, uint64_t(i)),
                                       samples);
        }
        return sum;
    } else {
        draw_far_cluster(pr, src, rcv_leaf, R.pocket);
    }
    // Same leaf twice: one sample (fewer to keep per point).
    merge_samples(samples, first);
    return t;
}

}  // namespace

bool PointRayStream::occluded(const Vec3& a, const Vec3& b) {
    const int k = n++;
    bool blocked;
    if (old && old->count <= 64 && k < old->count && !changed.meets(a, b)) {
        blocked = ((old->blocked >> k) & 1) != 0;
    } else {
        blocked = vis.occluded(a, b);
        ++cast;
    }
    if (blocked && k < 64) out.blocked |= uint64_t(1) << k;
    out.count = n;
    return blocked;
}

PointTransfer point_transfer(const Hierarchy& h, PointRayStream& rays_out, int src, const Vec3& x, const Vec3& n,
                             int rcv_leaf, int rays, uint64_t seed, std::vector<std::pair<int, float>>& samples) {
    return point_transfer_with(h, rays_out, src, x, n, rcv_leaf, rays, seed, samples);
}

Link limit_link(const Hierarchy& h, const Visibility& vis, const Link& base, int rays, uint64_t seed) {
    Link l = base;
    const Node& Q = h.nodes[size_t(l.rcv)];
    if (Q.is_cluster()) return l;
    const Cubature cub = cubature(Q.poly);
    const int per_point = std::max(2, rays / std::max(cub.n, 1));
    l.K = l.K_unoccluded = 0;
    l.samples.clear();
    double fmin = 1e300, fmax = 0;
    bool any_clear = false, any_blocked = false;
    for (int j = 0; j < cub.n; ++j) {
        PointRayStream rs(vis);
        const size_t first = l.samples.size();
        const PointTransfer t = point_transfer(h, rs, l.src, cub.p[size_t(j)], Q.normal, l.rcv, per_point,
                                               Hierarchy::mix(seed, uint64_t(j) + 1), l.samples);
        const double w = cub.w[size_t(j)];
        for (size_t k = first; k < l.samples.size(); ++k) l.samples[k].second *= float(w);
        l.K += w * t.F;
        l.K_unoccluded += w * t.F_unoccluded;
        fmin = std::min(fmin, t.F_unoccluded);
        fmax = std::max(fmax, t.F_unoccluded);
        any_clear |= t.F > 0;
        any_blocked |= t.partial || (t.F_unoccluded > 0 && !(t.F > 0));
    }
    merge_samples(l.samples);
    l.vis = l.K_unoccluded > 0 ? l.K / l.K_unoccluded : 0.0;
    l.dK = fmax > fmin ? fmax - fmin : 0.0;
    l.partial = any_clear && any_blocked;
    l.blocked = l.K_unoccluded > 0 && !any_clear;
    l.ray_count = -1;  // its rays are the point transfers': none recorded for replay
    return l;
}

Link evaluate_link(const Hierarchy& h, const Visibility& vis, int src, int rcv, int rays, uint64_t seed) {
    RayLog log{vis};
    Link l = evaluate_with(h, log, src, rcv, rays, seed);
    log.store(l);
    return l;
}

namespace {
// Visibility where every ray is clear.
struct ClearView {
    bool occluded(const Vec3&, const Vec3&) const { return false; }
    bool hidden_by(const Vec3&, const Vec3&, double, int) const { return false; }
};
}  // namespace

Link evaluate_link_unoccluded(const Hierarchy& h, int src, int rcv, int rays, uint64_t seed) {
    return evaluate_with(h, ClearView{}, src, rcv, rays, seed);
}

Link reevaluate_link(const Hierarchy& h, const Visibility& vis, const Link& old, int rays, uint64_t seed,
                     const std::vector<Aabb>& changed) {
    if (old.ray_count < 0) return evaluate_link(h, vis, old.src, old.rcv, rays, seed);
    RayReplay replay{{vis}, old, changed};
    Link l = evaluate_with(h, replay, old.src, old.rcv, rays, seed);
    replay.store(l);
    return l;
}

bool hull_meets(const Vec3& x, const Aabb& box, const std::vector<Aabb>& clips) {
    // The rays' ends are lifted off their surfaces by 1e-6 of the scene (point_transfer).
    const Aabb px = Aabb::around(x, 1e-5);
    const Aabb bx = box.grown(1e-5);
    for (const Aabb& c : clips)
        if (c.meets_shaft(px, bx)) return true;
    return false;
}

}  // namespace radiosity
