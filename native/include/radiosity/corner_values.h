// Per-corner read-out of the solution's leaves, where no final gather gives a corner its value
// (gather_rays 0, an object whose colours are not read, corners not written): the radiance
// (or any per-leaf quantity) of the leaf element at each corner, averaged over the faces that
// share the vertex unless a crease or a contact line separates them.
#pragma once
#include <functional>
#include <vector>

#include "radiosity/direct_light.h"
#include "radiosity/hierarchy.h"
#include "radiosity/scene.h"

namespace radiosity {

// What a read-out reads, borrowed for the call.
struct CornerRead {
    const Hierarchy& h;
    const SceneDesc& scene;
    const DirectLight& direct;  // which corners lie on a contact line (an edge for the averaging)
    double crease_angle_deg;    // Settings::crease_angle_deg
};

// Per corner of `object`, RGB interleaved: `leaf_value` of the leaf at the corner, averaged
// over the vertex's faces within the crease angle and on the same side of a contact.
// out_of_range for an unknown object.
std::vector<float> leaf_corner_values(const CornerRead& r, int object, const std::function<Rgb(int)>& leaf_value);
// The final gather's per-corner values `gathered` where it traced points, the leaves' at
// corners not written, or the leaves' everywhere when it traced none (`gathered` empty).
std::vector<float> gathered_or_leaves(const CornerRead& r, int object, std::vector<float> gathered,
                                      const std::function<Rgb(int)>& leaf_value);

}  // namespace radiosity
