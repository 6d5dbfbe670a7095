// Rays replayed after a move: the boxes where geometry moved (MovedBoxes) and what a stream of
// rays replayed from its record holds (ReplayedRays); the point transfers' and the lamps'
// streams (transfer.h, lights.cpp) add how their records store outcomes.
#pragma once
#include <cstdint>
#include <vector>

#include "radiosity/vec.h"

namespace radiosity {

// The boxes where geometry moved since some rays were recorded (a move's old and new boxes),
// for a replay to ask which rays it must cast again; most segments are turned away by the
// boxes' union first (a moved collection's parts give a dozen boxes in one place).
struct MovedBoxes {
    explicit MovedBoxes(const std::vector<Aabb>* b = nullptr) : boxes(b) {
        if (b)
            for (const Aabb& x : *b) all.grow(x);
    }
    bool meets(const Vec3& a, const Vec3& b) const { return all.meets_segment(a, b) && meets_any(*boxes, a, b); }
    const std::vector<Aabb>* boxes;
    Aabb all;
};

class Visibility;
// What a stream of replayed rays holds (PointRayStream, LampRayStream): its rays are cast
// through `vis`, or, with `old` (the record of the same rays: same seed and count) and
// `changed` (boxes where geometry moved since), a ray that meets none of the boxes takes its
// recorded outcome. `out` is the fresh record; `cast` counts the rays really cast.
template <class Record>
struct ReplayedRays {
    ReplayedRays(const Visibility& v, const Record* o, const std::vector<Aabb>* c)
        : vis(v), old(o), changed(o ? c : nullptr) {}
    const Visibility& vis;
    const Record* old = nullptr;
    MovedBoxes changed;
    Record out;
    int64_t cast = 0;
};

}  // namespace radiosity
