// Links: the energy transports of hierarchical radiosity (paper 2 and 3.1.1). A link is
// directional (sender -> receiver); both ends keep its index so dynamic updates can find
// every link of a moved object. A refined link stays as an inactive history link (3.4).
#pragma once
#include <cstdint>
#include <utility>
#include <vector>

#include "radiosity/vec.h"

namespace radiosity {

struct Link {
    int src = -1, rcv = -1;
    int parent = -1;       // the link this one refined: its history link
    // must_refine links: an upper bound of the coupling any point below the receiver can get
    // from the sender (coupling_bound). While the light it may carry is under the threshold,
    // the oracle keeps the link as it is instead of splitting it.
    float K_bound = 1;
    // Coupling. Element receiver: G_rcv += K * L_src. Cluster receiver: K * L_src is the
    // flux density (irradiance / pi on a surface facing the sender); each surface below the
    // receiver takes it times its own cosine toward `dir` (oriented clusters).
    double K = 0;
    double K_unoccluded = 0;
    double dK = 0;         // spread of the kernel over the receiver's cubature points
    double vis = 1;        // visibility fraction in [0,1]
    Vec3 dir;              // unit, sender centre -> receiver centre
    double dist = 0;       // centre distance
    bool active = true;
    bool cluster = false;  // either end is a cluster
    bool partial = false;  // some rays blocked, some not
    bool settled = false;  // the 3.5 criterion found the receiver's form factor converged
    bool must_refine = false;  // bounding spheres overlap: the point model is invalid
    bool outline = false;  // an emitting sender's outline crosses the receiver: its kernel falls to ~0 within it
    bool occluded = false; // fully occluded: kept (not gathered) so a move can reopen it
    // A cluster link whose rays were all blocked. It stays active with K = 0 so that the
    // oracle weighs the light the rays may have missed (oracle.cpp) instead of splitting it
    // down to element pairs unconditionally.
    bool blocked = false;
    bool dead = false;     // removed by a dynamic update or an un-refinement
    bool rejudge = false;  // re-evaluated by an update: the oracle must look at it again
    // Split by closure-driven refinement (refinement.h), not by the oracle: the split answers
    // the geometry (a leaf below sees less than this link's receiver), not the light level,
    // so un-refinement (3.4) keeps it.
    bool closure_split = false;
    // A history link whose rays may have changed with a move (some pass through a moved box)
    // but which was not evaluated since: its K, vis and samples are of the old placement.
    // Un-refinement judges it without rays first and evaluates it before taking it back
    // (Refinement::freshen_stale); nothing else reads a history link's values.
    bool stale = false;
    int first_child = -1;  // history tree: the links that refined this one
    int next_sibling = -1;
    // Outcomes of the visibility rays of its last evaluation, in the order they were cast
    // (transfer.cpp): bit k of ray_blocked is set when ray k was blocked, of ray_self when
    // what blocked it was the receiving point's own object. After a move an update casts
    // again only the rays through a moved object's old or new box and takes the others'
    // outcomes from here (reevaluate_link). ray_count < 0: none kept (more than 64 rays, or
    // the record no longer matches the geometry: Solver keeps this true).
    int ray_count = -1;
    uint64_t ray_blocked = 0, ray_self = 0;
    Rgb value;             // cluster receivers: K * L_src of the current iteration
    // Cluster senders and subdivided element senders: the unoccluded visibility samples (the
    // element holding the ray's end on the sender, as refined when the link was evaluated;
    // kernel weight). The sender's radiance toward the receiver is their weighted mean, so
    // parts of the sender hidden from the receiver (self-occlusion, back faces, the ceiling
    // right above a lamp hanging under it) neither dilute nor add to it. Surface roots'
    // area averages here would let the bright ceiling right above a lamp shine past the lamp
    // through the few visible points of its polygon, onto every receiver.
    std::vector<std::pair<int, float>> samples;

    // Whether the link stays active after an evaluation: it carries light, or must be split
    // before it can say, or its blocked rays leave the oracle to weigh what they may miss.
    // Otherwise it is fully occluded (kept aside so that a move can reopen it).
    bool transports() const { return must_refine || K > 0 || blocked; }
};

}  // namespace radiosity
