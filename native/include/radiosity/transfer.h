// Evaluation of one link, and of what one sender sends to one point (the final gather): form
// factor (analytic point-to-polygon kernel at the receiver's cubature points for surfaces;
// oriented point model for clusters) times a visibility fraction from Embree rays between
// jittered points of sender and receiver.
#pragma once
#include <cstdint>
#include <vector>

#include "radiosity/hierarchy.h"
#include "radiosity/link.h"
#include "radiosity/replay.h"
#include "radiosity/visibility.h"

namespace radiosity {

// Fills K, K_unoccluded, dK, vis, dir, dist, cluster, partial, must_refine of a link
// src -> rcv. `rays` is the visibility ray budget; `seed` makes the jitter reproducible.
Link evaluate_link(const Hierarchy& h, const Visibility& vis, int src, int rcv, int rays, uint64_t seed);

// evaluate_link again for a link whose ends did not change, after the geometry changed only
// inside `changed` (the old and new boxes of moved objects) since `old` was evaluated: a ray
// that passes through none of them has the outcome old recorded, so only the others are
// cast. The result equals evaluate_link's, bit for bit, with a fresh record. Without a
// record in `old` it is evaluate_link.
Link reevaluate_link(const Hierarchy& h, const Visibility& vis, const Link& old, int rays, uint64_t seed,
                     const std::vector<Aabb>& changed);

// evaluate_link as if nothing stood between the ends: no ray is cast (vis 1, nothing
// partial or blocked). An update judges with it whether a history link it left stale might
// be taken back (Refinement::freshen_stale) before paying for its rays.
Link evaluate_link_unoccluded(const Hierarchy& h, int src, int rcv, int rays, uint64_t seed);

// What sender node `src` sends to one point (the output's final gather): x with unit normal n
// on a surface whose leaf is `rcv_leaf` (only the sender's surfaces in that leaf's pocket
// take part). Appends to `samples` (sender leaf, weight) pairs whose weighted sum of leaf
// radiances is the irradiance / pi arriving at x from src, visibility included, so their
// weights sum to the point's coupling with src. An element sender: the exact point-to-polygon
// form factor times the kernel-weighted share of clear rays, each landing on the leaf it
// hits; a cluster: its surfaces drawn by projected area toward x, weighted by the true
// kernel over that density. `rays` rays, jittered by `seed`.
struct PointTransfer {
    double F = 0;            // coupling, visibility included (sum of the appended weights)
    double F_unoccluded = 0;
    int cast = 0;            // rays that count (cast or replayed; PointRayStream::cast: cast)
    bool partial = false;    // some rays blocked, some clear
    // Over the clear rays, their weight over the distance they went: F / inv_dist is the
    // harmonic mean distance to what the point sees of the sender (surfaces turned more than
    // 60 degrees from the point's own only: transfer.cpp).
    double inv_dist = 0;
    // Parts of one sender (a cluster's children or surfaces) add up.
    PointTransfer& operator+=(const PointTransfer& o) {
        F += o.F;
        inv_dist += o.inv_dist;
        F_unoccluded += o.F_unoccluded;
        cast += o.cast;
        partial |= o.partial;
        return *this;
    }
};
// The outcomes of a point transfer's rays, in the order cast (blocked: bit k for ray k; kept
// for up to 64 rays).
struct PointRays {
    int count = 0;
    uint64_t blocked = 0;
};
// The rays of one point transfer, replayed (ReplayedRays) from the same transfer's record
// where they meet no moved box: the segment and everything along it are the same.
struct PointRayStream : ReplayedRays<PointRays> {
    explicit PointRayStream(const Visibility& v, const PointRays* o = nullptr, const std::vector<Aabb>* c = nullptr)
        : ReplayedRays(v, o, c) {}
    int n = 0;
    bool occluded(const Vec3& a, const Vec3& b);
};
PointTransfer point_transfer(const Hierarchy& h, PointRayStream& rays_out, int src, const Vec3& x, const Vec3& n,
                             int rcv_leaf, int rays, uint64_t seed, std::vector<std::pair<int, float>>& samples);

// Whether any ray from x to `box` could meet one of `clips` (a move's old and new boxes):
// the box hull of the two meets one of them (a shaft test on boxes, with the rays' lift off
// their surfaces as margin).
bool hull_meets(const Vec3& x, const Aabb& box, const std::vector<Aabb>& clips);

// A link whose point model fails (Link::must_refine: the ends overlap or straddle each other's
// planes) into an element receiver, when neither end may split further (the resolution limit:
// a curved object's own small sub-clusters seen from its faces). evaluate_link leaves its
// coupling 0 and the light it carries would be lost; here it is the cubature average of
// point_transfer at the receiver's points, the output's own estimator (exact kernels for
// element senders, projected-area draws for clusters), with visibility. Keeps must_refine; no
// ray record (an update evaluates it afresh). A cluster receiver: `base` unchanged.
Link limit_link(const Hierarchy& h, const Visibility& vis, const Link& base, int rays, uint64_t seed);

// Unoccluded element-to-element coupling of a receiver polygon (not necessarily a node yet)
// from an element sender: the cubature average of the point-to-polygon form factor.
double unoccluded_coupling(const Poly& rcv, const Vec3& rcv_n, const Node& src);
// The same from the cubature of the receiver's 4^depth quadtree descendants: for kernels that
// vary within the receiver more than a low-order rule can follow.
double unoccluded_coupling(const Poly& rcv, const Vec3& rcv_n, const Node& src, int depth);

// Radiance a link carries from its sender: an element's own radiance; for a cluster the
// mean over the link's visible samples, else a projected-area estimate from the axis bins.
Rgb sender_radiance(const Hierarchy& h, const Link& l);
// An upper bound of the coupling (Link::K) that any point of node rcv's surfaces can get from
// node src's, from their boxes alone (Link::K_bound; 1 when the boxes meet).
double coupling_bound(const Hierarchy& h, int src, int rcv);

}  // namespace radiosity
