// The oracle (oracle.h): the error-threshold test of a link, with the paper's 3.5 progressive
// criterion, and which elements may split. Its parts, in order: the threshold a link is judged
// by, the errors of a link (point model, visibility, sender spread), the end to split or the
// settlement, and the rules that let a leaf split below the area floor (an emitter's outline,
// a narrow gap).
#include <algorithm>
#include <cmath>

#include "radiosity/oracle.h"
#include "radiosity/transfer.h"

namespace radiosity {

// The threshold a link's errors are compared with: the scene-wide one, error_threshold * L_ref
// (a scene-wide reference radiance), independent of scene scale and light intensity; once the
// light is known, scaled by the receiver's radiance relative to L_ref, down to threshold_floor
// (a dim receiver is judged by a relative error, as a viewer sees it).
double Oracle::link_threshold(const Node& Q) const {
    const double f = settings_.threshold_floor;
    if (!t_.light_known || f >= 1.0 || t_.reference <= 0) return t_.threshold;
    return t_.threshold * std::min(1.0, std::max(Q.L.max() / t_.reference, f));
}

namespace {

// The oriented point model's relative error on a cluster link: it grows with (size /
// distance).
// Near field: the kernel at the receiver's nearest surfaces exceeds the centre-to-centre
// value by (dist / gap)^2, so without this term a close, bright neighbour (the floor beside a
// box) goes under-refined and the box's sides dark. Capped so far-field links keep the
// plain term.
// An element end seen at a grazing angle: the point model takes its cosine toward the other
// end's centre, but parts of an extended other end lie up to asin((r_P + r_Q) / dist) off
// that direction, where the cosine is larger (the side of a Cornell block and the light). Its
// growth bounds the error; uncapped, since Ku * (growth - 1) <= projected area / (pi r^2).
// (What each term fixed, measured: docs/decisions.md, "The oracle's point-model error".)
double point_model_error(const Link& l, const Node& P, const Node& Q) {
    const double gap = std::max(l.dist - P.radius - Q.radius, 1e-3 * l.dist);
    double geo = std::min(8.0, std::max(std::min(1.0, 2.0 * (P.radius + Q.radius) / l.dist), (l.dist / gap) * (l.dist / gap) - 1.0));
    const double sa = std::min(1.0, (P.radius + Q.radius) / l.dist), ca = std::sqrt(1.0 - sa * sa);
    auto growth = [&](double c) {  // cos(theta - alpha) / cos(theta)
        return c > 0 ? std::min(1.0, c * ca + std::sqrt(std::max(0.0, 1.0 - c * c)) * sa) / c : 1.0;
    };
    double cos_growth = 1.0;
    if (!P.is_cluster()) cos_growth *= growth(dot(P.normal, l.dir));
    if (!Q.is_cluster()) cos_growth *= growth(-dot(Q.normal, l.dir));
    geo = std::max(geo, cos_growth - 1.0);
    return geo;
}

}  // namespace

// The oracle. Errors are in radiance units at the receiver, compared with link_threshold.
Oracle::Judgement Oracle::judge(const Link& l) const {
    const Node& P = h_.nodes[l.src];
    const Node& Q = h_.nodes[l.rcv];
    const double threshold = link_threshold(Q);
    Judgement j;
    const double rho = Q.is_cluster() ? Q.rho_max : Q.rho.max();
    const double Lp = sender_radiance(h_, l).max();
    // The sender's radiance range below it; a leaf's own is its direct light's spread over
    // its children (a floor leaf straddling a shadow's edge): a receiver close by reads that
    // leaf's average as if it were uniform (a slab's underside 15 cm over the floor lit
    // through the average of the shadowed floor under it and the lit floor past its edge).
    double dLp = (P.Lmax - P.Lmin).max();
    if (!P.is_cluster() && P.children.empty()) dLp = std::max(dLp, P.rho.max() * direct_light_.spread(l.src));
    double err_rcv = 0, err_src = 0;
    if (l.must_refine) {
        // The point model says nothing: all the light the link may carry is at stake, absorbed
        // as well as reflected (a black receiver's irradiance is what an energy balance
        // counts). A sender is taken as bright as the scene's reference at least, whatever
        // light it has so far: the judgement is then the same in a full solve's first waves
        // and in an update's.
        const double Lmax = std::max({Lp, P.Lmax.max(), t_.reference});
        err_rcv = err_src = Lmax * double(l.K_bound);
    } else if (!l.cluster) {
        err_rcv = l.settled ? 0.0 : rho * Lp * l.dK;
        err_src = rho * l.K * dLp;
    } else {
        // The point model's error; a partly occluded cluster link cannot place its shadow.
        const double geo = point_model_error(l, P, Q);
        double visterm = l.partial ? 2.0 * std::min(l.vis, 1.0 - l.vis) + 0.25 : 0.0;
        err_rcv = rho * Lp * l.K_unoccluded * (geo + visterm);
        // All rays blocked: what may have been missed is about the visible fraction that n
        // rays fail to see with 95 % confidence (the rule of three, 3 / n), at the
        // point model's coupling (larger in the near field).
        if (l.blocked) err_rcv = rho * Lp * l.K_unoccluded * std::max(1.0, geo) * 3.0 / settings_.rays_per_link;
        err_src = rho * l.K * dLp;
    }
    if (std::max(err_rcv, err_src) <= threshold) return j;
    const bool ps = can_split(l.src) || splits_at_gap(l.rcv, l.src, l, err_src, threshold),
               qs = can_split(l.rcv) || splits_at_outline(l, err_rcv, threshold) || splits_at_gap(l.src, l.rcv, l, err_rcv, threshold);
    if (!ps && !qs) return j;  // at the resolution limit
    j.side = split_side(l, P, Q, err_rcv, err_src, threshold, ps, qs);
    if (j.side == Side::Rcv && settles(l, P, Q, rho, Lp, threshold, err_src, j.settled_K)) j.side = Side::Settle;
    return j;
}

// Which end of a link over the threshold to split (Keep: neither can be), given its errors on
// either side and whether each end can split.
Oracle::Side Oracle::split_side(const Link& l, const Node& P, const Node& Q, double err_rcv, double err_src,
                                double threshold, bool ps, bool qs) {
    // A partly occluded link into a cluster cannot tell which of its surfaces are hidden
    // (a closed object's inner faces, or the part in another object's shadow): sharing the
    // flux by cosine would light hidden faces and dim the visible ones. Split the receiver.
    if (l.cluster && l.partial && Q.is_cluster()) return Side::Rcv;
    Side prefer;
    if (l.cluster || l.must_refine) {
        // Split the larger end (clusters by bounding sphere, elements by area). Ends of one
        // size split the receiver, where the output lives: decided by the last bits of two
        // equal areas, the choice could flip with a move's rounding.
        double sp = P.is_cluster() ? kPi * P.radius * P.radius : P.area;
        double sq = Q.is_cluster() ? kPi * Q.radius * Q.radius : Q.area;
        prefer = sp > sq * (1.0 + 1e-9) ? Side::Src : Side::Rcv;
    } else {
        prefer = err_rcv >= err_src ? Side::Rcv : Side::Src;
    }
    if (l.cluster || l.must_refine) {
        // The point model needs either end smaller: split whichever can be.
        if (prefer == Side::Src && !ps) prefer = Side::Rcv;
        if (prefer == Side::Rcv && !qs) prefer = Side::Src;
    } else {
        // Between elements each error term names its own cure: splitting the sender does not
        // reduce the kernel's spread over the receiver, and vice versa.
        if (prefer == Side::Rcv && !qs) prefer = err_src > threshold && ps ? Side::Src : Side::Keep;
        if (prefer == Side::Src && !ps) prefer = err_rcv > threshold && qs ? Side::Rcv : Side::Keep;
    }
    return prefer;
}

// 3.5: between mutually visible surfaces, refine the receiver only if its children's
// area-averaged form factor differs from the parent's by more than epsilon. (The paper's
// second test, sum of F_{q,p_i}, holds exactly for our analytic kernel.) True when the link
// may settle instead, with the children's mean coupling in `settled_K`.
bool Oracle::settles(const Link& l, const Node& P, const Node& Q, double rho, double Lp, double threshold,
                     double err_src, double& settled_K) const {
    if (!(settings_.progressive_refinement && !l.cluster && !l.partial && l.vis >= 1.0 && !Q.is_cluster()))
        return false;
    // We also ask the children to agree with each other: our output is per corner, so a
    // receiver must still split where its children would show a gradient.
    double khat = 0, kmin = 1e300, kmax = -1e300;
    for (int k = 0; k < 4; ++k) {
        Poly c = Q.poly.child(k);
        double kc = unoccluded_coupling(c, Q.normal, P);
        khat += c.area() * kc;
        kmin = std::min(kmin, kc);
        kmax = std::max(kmax, kc);
    }
    khat /= Q.area;
    if (khat > 0 && std::fabs(khat - l.K_unoccluded) / khat <= settings_.error_threshold &&
        rho * Lp * (kmax - kmin) <= threshold && err_src <= threshold) {
        settled_K = khat;
        return true;
    }
    return false;
}

bool Oracle::can_split(int id) const {
    const Node& n = h_.nodes[id];
    // A cluster smaller than four of the smallest elements the preset resolves, in its
    // surfaces' area and in its extent, is at the resolution limit, as such an element is: its
    // links stay cluster links (the final gather reads its surfaces from each output point).
    // Splitting it went down to pairs of a subdivided Suzanne's polygons. A long thin
    // one (fan pieces across an n-gon) and an emitting one still split.
    if (n.is_cluster())
        return !n.children.empty() && (n.area >= 4.0 * t_.min_area || kPi * n.radius * n.radius >= 4.0 * t_.min_area ||
                                       h_.emits(id, Hierarchy::Unknown::Emits));
    if (!n.children.empty()) return true;
    if (elements_ + 4 > settings_.max_elements) return false;
    return n.area * 0.25 >= t_.min_area;
}

// An emitter's outline across a receiver leaf (a lamp just under a ceiling: the ceiling over it
// bright, beside it dark, within one leaf): the leaf's average shines past the emitter into the
// room as if the whole leaf were lit. Such a leaf splits on below the area floor
// (may_split_below_floor) while the emitter's light on it is still well over the threshold:
// the outline is a line, so this costs elements in proportion to its length, not to an area.
bool Oracle::splits_at_outline(const Link& l, double err_rcv, double threshold) const {
    constexpr double kOverThreshold = 4.0;
    return l.outline && err_rcv > kOverThreshold * threshold && may_split_below_floor(l.rcv);
}

// A leaf element the outline and gap rules (and a lamp's shadow edge, DirectLight::refine) may
// split below the area floor: down to Settings::below_floor_levels quadtree levels under it,
// within the element cap.
bool Oracle::may_split_below_floor(int id) const {
    const Node& n = h_.nodes[id];
    const double share = std::ldexp(1.0, -2 * settings_.below_floor_levels);
    return settings_.below_floor_levels > 0 && !n.is_cluster() && n.children.empty() &&
           n.area * 0.25 >= share * t_.min_area && elements_ + 4 <= settings_.max_elements;
}

namespace {

// The distance between two elements' polygons, from nine points of each (corners, edge
// midpoints, centre) to the other polygon: enough to tell a gap narrower than a leaf.
double polygon_distance(const Node& a, const Node& b) {
    auto to = [](const Node& p, const Vec3& x) {
        const double h = dot(x - p.poly.v[0], p.normal), o = distance_outside(p.poly, p.normal, x);
        return std::sqrt(h * h + o * o);
    };
    auto from = [&to](const Node& p, const Node& q) {
        double m = to(q, p.center);
        for (int k = 0; k < p.poly.n; ++k) {
            const Vec3& v0 = p.poly.v[size_t(k)];
            const Vec3& v1 = p.poly.v[size_t((k + 1) % p.poly.n)];
            m = std::min({m, to(q, v0), to(q, (v0 + v1) * 0.5)});
        }
        return m;
    };
    return std::min(from(a, b), from(b, a));
}

// Whether a vertex of `p` lies on the plane of `q` (within tol): the two meet at a contact.
bool touches_plane(const Node& p, const Node& q, double tol) {
    for (int k = 0; k < p.poly.n; ++k)
        if (std::fabs(dot(p.poly.v[size_t(k)] - q.poly.v[0], q.normal)) <= tol) return true;
    return false;
}

}  // namespace

// A narrow gap (a cabinet 2 cm from a wall): the leaves across its mouth hold the room's light
// of their open part and pass it into the gap, and no single link into them is over the
// threshold. A leaf whose linked element is nearer than twice its width, without touching it
// (a contact is not a gap: the final gather resolves the corners there), splits below the
// area floor (may_split_below_floor) while the link's error on its side is over the
// threshold: a gap is as narrow as its walls are close, and costs elements along its mouth.
bool Oracle::splits_at_gap(int other, int id, const Link& l, double err, double threshold) const {
    const Node& a = h_.nodes[other];
    const Node& b = h_.nodes[id];
    if (l.cluster || a.is_cluster() || err <= threshold || !may_split_below_floor(id)) return false;
    const double size = std::sqrt(b.area), tol = 1e-3 * size;
    const double d = polygon_distance(a, b);
    return d > tol && d < 2.0 * size && !touches_plane(a, b, tol) && !touches_plane(b, a, tol);
}

}  // namespace radiosity
