// Evaluation of one link: form factor (analytic point-to-polygon kernel at the receiver's
// cubature points for surfaces; oriented point model for clusters) times a visibility
// fraction from Embree rays between jittered points of sender and receiver.
#pragma once
#include <cstdint>
#include <vector>

#include "radiosity/hierarchy.h"
#include "radiosity/link.h"
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

// Unoccluded element-to-element coupling of a receiver polygon (not necessarily a node yet)
// from an element sender: the cubature average of the point-to-polygon form factor.
double unoccluded_coupling(const Poly& rcv, const Vec3& rcv_n, const Node& src);

// Radiance a link carries from its sender: an element's own radiance; for a cluster the
// mean over the link's visible samples, else a projected-area estimate from the axis bins.
Rgb sender_radiance(const Hierarchy& h, const Link& l);

}  // namespace radiosity
