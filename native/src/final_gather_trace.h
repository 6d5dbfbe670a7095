// What the final gather keeps per output point (FinalGather::Point), per point-link transfer
// (Record), and one point to trace (Job): private to the final gather's sources
// (final_gather.cpp, shared_gather.cpp, near_field.cpp, near_direct.cpp, preview.cpp).
#pragma once
#include <cstdint>
#include <utility>
#include <vector>

#include "radiosity/final_gather.h"

namespace radiosity {

// One link's transfer to a point, as traced: its samples, coupling and ray outcomes.
struct FinalGather::Record {
    // The link's sender: a point reads each sender through one link, and what it finds
    // does not depend on the receiver node that holds the link (its seed is the point's
    // and the sender's), so after a split on the receiver side the record still serves.
    int src = -1;
    uint32_t begin = 0, end = 0;  // its samples in Point::samples
    float F = 0;                  // coupling, visibility included (for the closure)
    uint16_t rays = 0;            // ray budget it was traced with
    bool own = false;             // a link at the leaf itself (not inherited)
    bool refined = false;         // traced again with more rays (a shadow edge)
    bool emits = false;           // its sender emits, or holds a surface that does
    float inv_dist = 0;           // PointTransfer::inv_dist
    PointRays outcome;            // for replay after a move
};
struct FinalGather::Point {
    // Empties what a trace found (before tracing the point again); `gather`: it gathers all
    // its links, not only its emitters (a shared point).
    void reset(bool gather) {
        gathered = gather;
        reach = 0;
        samples.clear();
        records.clear();
        direct = Rgb{};
        lamp_rays = LampRays{};
        near = Rgb{};
        escapes = -1;
        c_own = c_inherited = 1;
        fill = 0;
        sealed = false;
    }
    // Frees what a trace found (an old point once the retrace has read it).
    void release() {
        std::vector<std::pair<int, float>>().swap(samples);
        std::vector<Record>().swap(records);
        std::vector<std::pair<int, float>>().swap(borrow);
        lamp_rays = LampRays{};
    }
    int object = -1, prim = -1, k = 0;  // the corner it was made for (first of its corners)
    Vec3 x, n;
    uint64_t seed = 0;
    int leaf = -1;       // the leaf holding it (its reflectance, emission, and fill radiance)
    bool covered = false;
    // Covered: the leaf of the covering polygon's other side at the point. What lies
    // beyond the contact is what Cycles' rays from there find (a box's dark inside under
    // it, the underside of the floor under the box's bottom), and that side's radiance is
    // what the point gathers; -1 when the covering polygon is one-sided.
    int beyond = -1;
    Rgb direct;          // lamps' irradiance / pi
    LampRays lamp_rays;  // its shadow rays' outcomes (replayed after a move)
    // Near-field correction (near_field.cpp), irradiance / pi: the senders a
    // hair from the point read at a point of theirs instead of their leaf's average.
    Rgb near;
    // Inside a closed solid (point_sealed): no light reaches it; a covered point so
    // sealed reads nothing beyond its contact either.
    bool sealed = false;
    int8_t escapes = -1;  // enclosed leaves only: whether the point's own escape rays find open space
    // Closure (as the solver's at the leaf): factors on own and inherited couplings, and
    // the share of the hemisphere taken to see the leaf's own radiance.
    double c_own = 1, c_inherited = 1, fill = 0;
    std::vector<std::pair<int, float>> samples;  // (node, weight): irradiance / pi = sum w L
    std::vector<Record> records;
    // A shared point (Config::share) traced only its lamps and emitting senders; its
    // bounced light is that of gathered points near it: (point, weight), weights summing
    // to 1. A gathered point lends within share x `reach` (0: lends nothing).
    bool gathered = true;
    float reach = 0;
    std::vector<std::pair<int, float>> borrow;
};
// One output point to trace: a corner, or the corners of one vertex sharing a normal and
// a contact state (final_gather.cpp make_jobs).
struct FinalGather::Job {
    int object = -1, prim = -1, k = 0;
    Vec3 x, n;
    int leaf = -1, surface = -1;
    bool covered = false;
    int beyond = -1;  // corner_covered
    uint64_t seed = 0;
};

}  // namespace radiosity
