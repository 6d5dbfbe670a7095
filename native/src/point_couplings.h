// A point's couplings as a final gather traces its links, for its closure (final_gather.cpp
// trace_point, near_field.cpp radiance_at): internal to the final gather.
#pragma once
#include <algorithm>
#include <cstddef>
#include <utility>

#include "radiosity/final_gather.h"
#include "radiosity/hierarchy.h"

namespace radiosity {

// A point's couplings as its links are traced (own or inherited, and the sampled part of each),
// and the closure factors they call for: one tally for the output points and the near field's.
struct PointCouplings {
    double own = 0, inherited = 0, s_own = 0, s_inherited = 0;
    void add(double F, bool is_own, bool sampled) {
        (is_own ? own : inherited) += F;
        if (sampled) (is_own ? s_own : s_inherited) += F;
    }
    ClosureFactors closure() const { return point_closure_factors(own, inherited, s_own, s_inherited); }
};

// The part of a link's coupling F to a point that counts toward its closure: none from an
// object that hides nothing (an area light: the ceiling behind it is seen too, so a wall
// beside one would sum to 1 + its form factor, and the closure would dim the wall's light),
// and from a cluster above objects all but the samples that landed on such objects.
inline double closing_coupling(const Hierarchy& h, int src, double F, const std::pair<int, float>* samples, size_t n) {
    if (!h.closes(src)) return 0.0;
    if (h.nodes[size_t(src)].object >= 0) return F;
    for (size_t i = 0; i < n; ++i)
        if (!h.closes(samples[i].first)) F -= double(samples[i].second);
    return std::max(F, 0.0);
}

}  // namespace radiosity
