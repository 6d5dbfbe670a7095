// The final gather's near field (near_field): a point a hair from another surface
// reads that surface's part near it at points gathered there (radiance_at, one level of the
// gather, nested), the two sides of the contact solved together (NearPlane).
#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

#include "final_gather_trace.h"
#include "point_couplings.h"
#include "radiosity/lights.h"
#include "radiosity/random.h"
#include "radiosity/transfer.h"

namespace radiosity {
namespace fg {

namespace {

// The part of a convex polygon inside an axis-aligned box (Sutherland-Hodgman over its six
// planes); n = 0 when nothing is left. At most 4 + 6 vertices.
int clip_to_box(const Poly& p, const Aabb& b, Vec3* out) {
    Vec3 buf[2][12];
    int n = p.n;
    for (int i = 0; i < n; ++i) buf[0][i] = p.v[size_t(i)];
    int cur = 0;
    for (int axis = 0; axis < 3 && n > 0; ++axis)
        for (int side = 0; side < 2 && n > 0; ++side) {
            const double lim = side ? b.hi[axis] : b.lo[axis];
            auto inside = [&](const Vec3& v) { return side ? v[axis] <= lim : v[axis] >= lim; };
            const Vec3* in = buf[cur];
            Vec3* o = buf[1 - cur];
            int m = 0;
            for (int i = 0; i < n && m < 11; ++i) {
                const Vec3& a = in[i];
                const Vec3& c = in[(i + 1) % n];
                const bool ia = inside(a), ic = inside(c);
                if (ia) o[m++] = a;
                if (ia != ic && m < 12) o[m++] = a + (c - a) * ((lim - a[axis]) / (c[axis] - a[axis]));
            }
            n = m;
            cur = 1 - cur;
        }
    for (int i = 0; i < n; ++i) out[i] = buf[cur][i];
    return n >= 3 ? n : 0;
}

}  // namespace

Rgb radiance_at(const Run& run, int m_id, const Vec3& sp, uint64_t seed, Counts& counts, NearScratch& scratch,
                NearPlane* wall) {
    // One level of the gather at a point of leaf m: its lamps and its links, a few rays each.
    const Solution& s = run.s;
    const Config& c = run.c;
    const Hierarchy& h = s.h;
    const Node& m = h.nodes[size_t(m_id)];
    Rgb g;
    const PointLight lamp = direct_light_at(s.scene, h, s.vis, sp, m.normal, false, std::max(4, c.light_samples / 8), seed);
    g += lamp.E;
    counts.rays += lamp.rays;
    std::vector<std::pair<int, bool>>& reaching = scratch.reaching;
    std::vector<std::pair<int, float>>& nested = scratch.nested;
    links_reaching(s, &run.occluded, m_id, reaching);
    // Russian roulette over the links: link l is gathered with probability q_l = min(1, n w_l /
    // W), w_l what it may bring (an estimate of its coupling at sp times its sender's radiance
    // plus the mean radiance, so that dark senders still count for the closure and the wall),
    // and its samples weighted 1 / q_l: unbiased, about n links a point in place of all of them.
    // A cluster link with no coupling of its own (the ends too close for the point model, at
    // the resolution limit) has no estimate: always gathered (w < 0).
    using Est = NearScratch::Estimate;
    std::vector<Est>& est = scratch.est;
    est.clear();
    double F_all = 0, FL_all = 0;
    for (const auto& r : reaching) {
        const Link& l = s.links[size_t(r.first)];
        const Node& P = h.nodes[size_t(l.src)];
        double F = l.K_unoccluded;
        if (!P.is_cluster()) F = P.pocket == m.pocket ? point_polygon_form_factor(sp, m.normal, P.poly, P.normal) : 0.0;
        else if (l.must_refine || !(F > 0)) F = -1.0;
        if (F < 0) {
            est.push_back({-1.0, 0.0});
            continue;
        }
        const double L = F > 0 ? sender_radiance(h, l).max() : 0.0;
        est.push_back({F, L});
        F_all += F;
        FL_all += F * L;
    }
    const double L_mean = F_all > 0 ? FL_all / F_all : 0.0;
    auto weight = [&](const Est& e) { return e.F < 0 ? -1.0 : e.F * (e.L + L_mean); };
    double W = 0;
    for (const Est& e : est) W += std::max(0.0, weight(e));
    const double n_links = std::max(8, c.rays / 8);
    PointCouplings couplings;
    Rgb own, all;
    for (size_t i = 0; i < reaching.size(); ++i) {
        const auto& [li, is_own] = reaching[i];
        const Link& l = s.links[size_t(li)];
        const uint64_t lseed = Hierarchy::mix(seed, uint64_t(li));
        const double w = weight(est[i]);
        const double q = W > 0 && w >= 0 ? std::min(1.0, n_links * w / W) : 1.0;
        if (q < 1.0 && !(Rng(Hierarchy::mix(lseed, 0x7217u)).next() < q)) continue;
        nested.clear();
        PointRayStream rs(s.vis);
        const PointTransfer tr = point_transfer(h, rs, l.src, sp, m.normal, m_id, std::max(2, c.min_rays / 2), lseed, nested);
        counts.rays += rs.cast;
        const double inv_q = 1.0 / q;
        for (auto& sm : nested) sm.second = float(double(sm.second) * inv_q);
        Rgb e;
        for (const auto& [k, wk] : nested) {
            const Node& nk = h.nodes[size_t(h.live_element(k))];
            e += nk.L * double(wk);
            if (wall && !nk.is_cluster() && nk.surface >= 0) wall->read(h, nk, double(wk));
        }
        all += e;
        if (is_own) own += e;
        couplings.add(closing_coupling(h, l.src, tr.F * inv_q, nested.data(), nested.size()), is_own,
                      h.nodes[size_t(l.src)].is_cluster());
    }
    ClosureFactors cf;
    if (s.enclosure.enclosed(m_id) == 1) cf = couplings.closure();
    g += closure_gathered(own, all, cf.c_own, cf.c_inherited, cf.fill, m.L);
    if (wall) wall->couple(h, sp, m.normal);
    return m.emission + h.rho_at(m_id, sp) * g;  // a texture's value at sp, not the leaf's mean
}

void NearPlane::read(const Hierarchy& h, const Node& k, double w) {
    const Node& g = h.nodes[size_t(h.surfaces[size_t(k.surface)].root)];
    if (dot(g.normal, n) < 1.0 - 1e-9 || std::abs(dot(g.poly.v[0], n) - offset) > tol) return;
    auto it = std::find_if(seen.begin(), seen.end(), [&](const std::pair<int, std::pair<double, Rgb>>& e) { return e.first == k.surface; });
    if (it == seen.end()) seen.push_back({k.surface, {w, k.L * w}});
    else it->second.first += w, it->second.second += k.L * w;
}

int NearPlane::surface_at(const Hierarchy& h, const Vec3& q) const {
    for (int sf : surfaces) {
        const Node& g = h.nodes[size_t(h.surfaces[size_t(sf)].root)];
        if (distance_outside(g.poly, g.normal, q) <= 1e-9 * h.scene_diag) return sf;
    }
    return -1;
}

void NearPlane::couple(const Hierarchy& h, const Vec3& sp, const Vec3& sn) {
    const double d = dot(sp, n) - offset;
    F = F_all = 0;
    WL = WL_all = Rgb{};
    if (!(d > 0)) return;
    const double R = kNearReach * d;
    const Aabb all = Aabb::around(sp, R);
    const std::optional<Aabb> in = all.intersection(region);
    for (const auto& [surface, wl] : seen) {
        const Node& g = h.nodes[size_t(h.surfaces[size_t(surface)].root)];
        Vec3 part[12];
        for (int pass = 0; pass < 2; ++pass) {
            if (pass == 1 && !in) break;
            const int np = clip_to_box(g.poly, pass == 0 ? all : *in, part);
            if (np == 0) continue;
            const double f = std::min(point_polygon_form_factor(sp, sn, part, np, g.normal), wl.first);
            if (!(f > 0)) continue;
            (pass == 0 ? F_all : F) += f;
            (pass == 0 ? WL_all : WL) += wl.second * (f / wl.first);
        }
        if (std::find(surfaces.begin(), surfaces.end(), surface) == surfaces.end()) surfaces.push_back(surface);
    }
    F = std::min(F, F_all);
}

// A point a hair from another surface (a floor corner 0.1 mm from a wall standing on it, a
// cube's foot corner over the floor) takes most of what it sees of that surface from its first
// millimetres: at distance d from the wall's plane, 90 % of the wall's form factor comes from
// within 10 d. The light there is not the wall leaf's average: on the shadow side of an object
// both sides of the contact go dark toward the edge (each sees mostly the other), on the lit
// side the floor right at a cube's foot has the floor's direct light at that spot. So the part
// of such a sender within R = 20 d of the point reads the radiance gathered at points s* of it
// (drawn as the kernel weighs them, a few d from the contact), from the sender leaf's own links
// -- one level of the gather, nested -- in place of the leaf's average; and since s* sees the
// point's own plane near it as much as the point sees the sender, the two are solved together
// (NearField::correction). Kept as a correction, F_near x (L(s*) - L_leaf), so that the samples
// stay what the rays found (a retrace keeps or replays them). Why the s* are many and
// stratified over both sides: docs/decisions.md, "The near field".
void near_field(const Run& run, Point& pt, Counts& counts, NearScratch& scratch) {
    NearField near(run, pt, counts, scratch);
    near.add_to(pt.near);
}

NearField::NearField(const Run& run, const Point& pt, Counts& counts, NearScratch& scratch)
    : run_(run), h_(run.s.h), pt_(pt), counts_(counts), own_(run.s.h.nodes[size_t(pt.leaf)]),
      near_points_(std::max(4, run.c.rays / 32)), side_(int(std::ceil(std::sqrt(2.0 * near_points_)))),
      max_stars_(std::max(8, near_points_ / 2)), scratch_(scratch), seen_(scratch.seen), wall_(scratch.wall),
      coplanar_(scratch.coplanar), stars_(scratch.stars) {}

void NearField::read_surfaces() {
    // (In the order the samples first read each surface, found through an index by surface.)
    std::vector<int>& at = scratch_.seen_index;
    if (at.size() < h_.surfaces.size()) at.resize(h_.surfaces.size(), -1);
    seen_.clear();
    for (const auto& [node, w] : pt_.samples) {
        const Node& m = h_.nodes[size_t(h_.live_element(node))];
        if (m.is_cluster() || m.surface < 0) continue;
        const double size = std::sqrt(m.area);
        int& k = at[size_t(m.surface)];
        if (k < 0) {
            k = int(seen_.size());
            seen_.push_back({m.surface, double(w), m.L * double(w), size * double(w)});
        } else {
            Seen& e = seen_[size_t(k)];
            e.W += double(w), e.WL += m.L * double(w), e.WS += size * double(w);
        }
    }
    for (const Seen& e : seen_) at[size_t(e.surface)] = -1;
}

Rgb NearField::uncorrected() const {
    Rgb S_own, S_all;
    for (const Record& r : pt_.records)
        for (uint32_t i = pt_.begin_of(r); i < r.end; ++i) {
            const Rgb e = h_.nodes[size_t(h_.live_element(pt_.samples[i].first))].L * double(pt_.samples[i].second);
            S_all += e;
            if (r.own) S_own += e;
        }
    return pt_.direct + closure_gathered(S_own, S_all, pt_.c_own, pt_.c_inherited, pt_.fill, own_.L);
}

void NearField::add_to(Rgb& near) {
    read_surfaces();
    S_ = uncorrected();
    wall_.n = pt_.n;
    wall_.tol = 1e-9 * h_.scene_diag;
    for (const Seen& sn : seen_) {
        if (sn.surface == own_.surface || !(sn.W > 0)) continue;
        Rgb corr;
        if (correction(sn, corr)) near += corr;
    }
}

bool NearField::near_part(const Seen& sn, const Node& root, double& d, double& F_near, Aabb& box) const {
    constexpr double kLeafShare = 0.05;  // R must be under this share of the sender polygon's size
    constexpr double kGapLeaf = 4.0;     // ... or the leaves read at least this many times wider than d
    constexpr double kGapShare = 0.05;   //     and its coupling to the point at least this
    d = dot(pt_.x - root.poly.v[0], root.normal);
    if (!(d > 0)) return false;
    // Near: a hair from the sender's polygon, or in a narrow gap in front of a sender whose
    // leaves are much wider than the gap (a cabinet's back 2 cm from the wall: the wall's
    // leaves there average the lit wall beside the cabinet with the dark wall behind it, and
    // the point sees the dark part) and that brings the point a real share of its light.
    const bool hair = kNearReach * d <= kLeafShare * std::sqrt(root.area);
    const bool gap = kGapLeaf * d < sn.WS / sn.W && sn.W >= kGapShare;
    if (!hair && !gap) return false;
    const double R = kNearReach * d;
    box = Aabb::around(pt_.x, R);
    Vec3 part[12];
    const int np = clip_to_box(root.poly, box, part);
    if (np == 0) return false;
    F_near = std::min(point_polygon_form_factor(pt_.x, pt_.n, part, np, root.normal), sn.W);
    return F_near > 0;
}

void NearField::bound_wall(const Node& root, double R) {
    // The point stands for its own plane only in front of the sender's plane as far as the
    // point sees it (the sender's polygons there, all of a cabinet's back in a 2 cm gap): past
    // the sender's edge (a box's corner, 0.1 mm away) the floor may be lit where the point is in
    // the box's shadow, and s* reads it at points gathered there (beyond()).
    wall_.offset = dot(pt_.n, own_.poly.v[0]);
    wall_.surfaces.clear();
    wall_.region.lo = root.poly.v[0];
    wall_.region.hi = root.poly.v[0];
    const double sender_offset = dot(root.normal, root.poly.v[0]);
    coplanar_.clear();
    for (const Seen& other : seen_) {
        const Node& g = h_.nodes[size_t(h_.surfaces[size_t(other.surface)].root)];
        if (dot(g.normal, root.normal) < 1.0 - 1e-9 || std::abs(dot(g.poly.v[0], root.normal) - sender_offset) > wall_.tol)
            continue;
        coplanar_.push_back(h_.surfaces[size_t(other.surface)].root);
        for (int k = 0; k < g.poly.n; ++k) wall_.region.grow(g.poly.v[size_t(k)]);
    }
    const Vec3 reach{R * std::abs(root.normal.x), R * std::abs(root.normal.y), R * std::abs(root.normal.z)};
    wall_.region = wall_.region.grown(reach);
}

NearField::Stars NearField::gather_stars(const Seen& sn, const Node& root, double d, double R, bool vary, uint64_t seed,
                                         Rng& rng) {
    // Points s* of the near part, drawn as the kernel weighs it: cosine-distributed directions
    // from x that meet the sender's plane within the box (the light there can change within
    // the near part: a shadow's edge at a leg's foot), stratified over the whole hemisphere
    // (the near part takes a share of it, half for a sender at right angles). Each gathers anew.
    const Vec3& x = pt_.x;
    const Vec3& n = pt_.n;
    const int surface_root = h_.surfaces[size_t(sn.surface)].root;
    const CosineStrata strata(n, side_);
    // Where the whole hemisphere meets the near part (a sender facing the point across a gap,
    // a board under a book) every stratum holds an s*: a stratified subset of them gathers,
    // every k-th along the strata's diagonals, from max_stars_ to twice that many.
    using Candidate = NearScratch::Candidate;
    std::vector<Candidate>& found = scratch_.found;
    found.clear();
    for (int tries = 0; tries < strata.count(); ++tries) {
        const Vec3 w = strata.direction(tries, rng);
        const double dn = -dot(w, root.normal);
        if (!(dn > 1e-6)) continue;
        const double t = d / dn;
        if (t > 1.7 * R) continue;
        const Vec3 sp = x + w * t;
        if (distance_outside(root.poly, root.normal, sp) > 1e-9 * h_.scene_diag) continue;
        const int m_id = h_.leaf_at(surface_root, sp);
        if (m_id >= 0) found.push_back({tries, sp, m_id});
    }
    const int k = std::max(1, int(found.size()) / max_stars_);
    const int pick = k > 1 ? std::min(k - 1, int(rng.next() * k)) : 0;
    Stars st;
    stars_.clear();
    for (const Candidate& cand : found) {
        if (k > 1 && (cand.stratum % side_ + cand.stratum / side_) % k != pick) continue;
        const Vec3& sp = cand.p;
        wall_.seen.clear();
        const Rgb Ls = radiance_at(run_, cand.leaf, sp, Hierarchy::mix(seed, uint64_t(cand.stratum)), counts_, scratch_, &wall_);
        const Rgb rho_s = h_.rho_at(cand.leaf, sp);
        st.B0 += Ls - rho_s * wall_.WL_all;
        if (vary) direct_->add_star(sp, rho_s, kNearReach * (dot(sp, n) - wall_.offset));
        st.Cout += rho_s * (wall_.F_all - wall_.F);
        st.Bout += rho_s * (wall_.WL_all - wall_.WL);
        st.C += rho_s * wall_.F;
        stars_.push_back(sp);
        ++st.got;
    }
    return st;
}

bool NearField::beyond(const Node& root, const Aabb& box, uint64_t seed, Rng& rng, Rgb& mean) {
    // The plane near s* but outside the point's neighbourhood: its radiance at a few points of
    // its own (a lit floor past a box's corner), not its leaves' average. The points are where
    // cosine directions from the s* meet the plane, so that they stand for what the s* see of
    // it (a slab's underside near its shadowed edge sees the dark floor there, not the lit
    // floor across the slab). Their mean; false when none was found.
    Vec3 su, sv;
    frame(root.normal, su, sv);
    Rgb aq;
    int gq = 0;
    const int nq = std::max(8, near_points_ / 2);
    for (int t = 0; t < 32 * nq && gq < nq; ++t) {
        const Vec3& sp = stars_[size_t(t) % stars_.size()];
        const double r2 = rng.next(), r1 = rng.next();  // named: the order is every compiler's
        const Vec3 w = cosine_direction(su, sv, root.normal, r1, r2);
        const double dn = dot(w, pt_.n);
        if (!(dn < -1e-6)) continue;
        const Vec3 p = sp + w * ((wall_.offset - dot(sp, pt_.n)) / dn);
        if (!box.contains(p) || wall_.region.contains(p)) continue;
        const int q_surface = wall_.surface_at(h_, p);
        if (q_surface < 0) continue;
        const int q_id = h_.leaf_at(h_.surfaces[size_t(q_surface)].root, p);
        if (q_id < 0) continue;
        aq += radiance_at(run_, q_id, p, Hierarchy::mix(seed, uint64_t(1000 + t)), counts_, scratch_);
        ++gq;
    }
    if (gq == 0) return false;
    mean = aq / double(gq);
    return true;
}

bool NearField::correction(const Seen& sn, Rgb& out) {
    const Node& root = h_.nodes[size_t(h_.surfaces[size_t(sn.surface)].root)];
    double d = 0, F_near = 0;
    Aabb box;
    if (!near_part(sn, root, d, F_near, box)) return false;
    const double R = kNearReach * d;
    const uint64_t seed = Hierarchy::mix(pt_.seed, Hierarchy::mix(root.key, 0x4ea7u));
    Rng rng(seed);
    bound_wall(root, R);
    // The plane's own direct light near x (near_direct.cpp), where a shadow's edge is near.
    if (!direct_) direct_.emplace(run_.s, run_.c, pt_, near_points_, counts_);
    const bool vary = direct_->applies(coplanar_, R);
    direct_->clear_stars();
    Stars st = gather_stars(sn, root, d, R, vary, seed, rng);
    if (st.got == 0) return false;
    if (vary) st.B0 += direct_->sum(root, sn.WL / sn.W, d, wall_, seed);
    if (st.Cout.max() > 0) {
        Rgb aq;
        if (beyond(root, box, seed, rng, aq)) st.B0 += st.Cout * aq;
        else st.B0 += st.Bout;
    }
    const Rgb B0 = st.B0 / double(st.got);
    const Rgb C = st.C / double(st.got);
    // s* sees the point's own plane near it too, and that part is what the point's
    // neighbourhood sends: L(s*) = B0 + C a, with a = e + rho E(x) the radiance at x. E(x) =
    // S - F_near Lbar + F_near L(s*) (S what the samples and lamps give, Lbar the average they
    // read of this sender), solved for E(x): the two sides of a contact light each other,
    // bounce after bounce (the shadow side of a box's foot goes dark on both faces, as each
    // sees mostly the other).
    const Rgb Lbar = sn.WL / sn.W;
    const Rgb corr = F_near * (B0 + C * (own_.emission + own_.rho * S_) - Lbar);
    // (Reflectances are under 1 and F_near, C under 1: den > 0; the floor is for safety.)
    const Rgb den = cmax(Rgb{1, 1, 1} - F_near * C * own_.rho, Rgb{1e-3, 1e-3, 1e-3});
    out = Rgb{corr.r / den.r, corr.g / den.g, corr.b / den.b};
    ++counts_.near;
    return true;
}

}  // namespace fg
}  // namespace radiosity
