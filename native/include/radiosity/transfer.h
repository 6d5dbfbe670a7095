// Evaluation of one link: form factor (analytic point-to-polygon kernel at the receiver's
// cubature points for surfaces; oriented point model for clusters) times a visibility
// fraction from Embree rays between jittered points of sender and receiver.
#pragma once
#include <cstdint>

#include "radiosity/hierarchy.h"
#include "radiosity/link.h"
#include "radiosity/visibility.h"

namespace radiosity {

// Fills K, K_unoccluded, dK, vis, dir, dist, cluster, partial, must_refine of a link
// src -> rcv. `rays` is the visibility ray budget; `seed` makes the jitter reproducible.
Link evaluate_link(const Hierarchy& h, const Visibility& vis, int src, int rcv, int rays, uint64_t seed);

// Unoccluded element-to-element coupling of a receiver polygon (not necessarily a node yet)
// from an element sender: the cubature average of the point-to-polygon form factor.
double unoccluded_coupling(const Poly& rcv, const Vec3& rcv_n, const Node& src);

// Directional radiance of a sender toward unit direction d (clusters: projected-area
// weighted estimate from their axis bins; elements: their radiance).
Rgb sender_radiance(const Node& src, const Vec3& d);

}  // namespace radiosity
