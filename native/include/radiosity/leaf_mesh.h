// The adaptive-mesh output: an object's front-side leaf elements as one mesh, made by
// Solver::leaf_mesh (leaf_mesh.cpp) and handed to the add-on, which builds a new object from it.
#pragma once
#include <cstdint>
#include <vector>

#include "radiosity/vec.h"

namespace radiosity {

// World-space vertices, Blender's polygon layout, one value per polygon. T-vertex free: a
// vertex of a finer neighbour that lies on a coarser element's edge is inserted into that
// element's boundary (an n-gon).
struct LeafMesh {
    std::vector<Vec3> vertices;
    std::vector<int32_t> loop_totals, corner_verts;
    std::vector<Rgb> values;           // per polygon
    std::vector<int32_t> source_face;  // per polygon: the input polygon it subdivides
};

}  // namespace radiosity
