// Helpers shared by the native tests: small scenes and read-outs of solved hierarchies.
#pragma once
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "radiosity/builtin_scenes.h"
#include "radiosity/geometry.h"
#include "radiosity/compare.h"
#include "radiosity/front_leaves.h"
#include "radiosity/solver.h"

namespace radiosity::testing {

// A move by t, as Solver::move_object takes it (row-major 4 x 4).
inline std::array<double, 16> translation(Vec3 t) { return {1, 0, 0, t.x, 0, 1, 0, t.y, 0, 0, 1, t.z, 0, 0, 0, 1}; }

// A Blender point light named "lamp" at p: intensity per channel, radius 0 = a true point.
inline LightDesc point_light(Vec3 p, double intensity, double radius = 0) {
    LightDesc l;
    l.name = "lamp";
    l.type = LightDesc::Type::Point;
    l.position = p;
    l.radius = radius;
    l.intensity = Rgb::all(intensity);
    return l;
}

// A 4 x 4 x 2.5 m room of n x n quads a face (object 0, reflectance 0.6, normals in) and a
// 1 m square lamp of radiance 10 just under its ceiling (object 1).
inline SceneDesc lamp_room(int n) {
    SceneDesc s;
    scenes::add_box(s, "room", -1, {0, 0, 0}, {4, 4, 2.5}, n, Rgb::all(0.6), {}, true);
    scenes::add_grid(s, "lamp", -1, {Vec3{1.5, 1.5, 2.49}, Vec3{1.5, 2.5, 2.49}, Vec3{2.5, 2.5, 2.49}, Vec3{2.5, 1.5, 2.49}}, 1,
                     1, {}, Rgb::all(10.0), false);
    return s;
}

inline Poly quad(Vec3 a, Vec3 b, Vec3 c, Vec3 d) {
    Poly p;
    p.n = 4;
    p.v = {a, b, c, d};
    return p;
}

// F from receiver polygon r to sender polygon s (the fraction of r's light reaching s):
// the point kernel integrated over r with an n x n midpoint rule on a grid of sub-polygons.
inline double form_factor(const Poly& r, const Poly& s, int levels = 6) {
    std::vector<Poly> cells{r};
    for (int l = 0; l < levels; ++l) {
        std::vector<Poly> next;
        for (const Poly& c : cells)
            for (int k = 0; k < 4; ++k) next.push_back(c.child(k));
        cells.swap(next);
    }
    const Vec3 rn = r.normal(), sn = s.normal();
    double sum = 0, area = 0;
    for (const Poly& c : cells) {
        Cubature cub = cubature(c);
        double a = c.area(), k = 0;
        for (int j = 0; j < cub.n; ++j) k += cub.w[j] * point_polygon_form_factor(cub.p[j], rn, s, sn);
        sum += a * k;
        area += a;
    }
    return sum / area;
}

// Area-weighted radiance of the front side of all polygons of an object.
inline Rgb object_front_radiance(const Solver& s, int object) {
    const Hierarchy& h = s.hierarchy();
    Rgb acc;
    double a = 0;
    for (const Primitive& p : h.prims) {
        if (p.object != object || p.front < 0) continue;
        const Node& n = h.nodes[h.surfaces[p.front].root];
        acc += n.L * n.area;
        a += n.area;
    }
    return acc / a;
}

// The ids of an object's front leaves (the elements its polygons' fronts end in), in
// for_each_front_leaf's order.
inline std::vector<int> front_leaf_ids(const Solver& s, int object) {
    std::vector<int> out;
    for_each_front_leaf(s.hierarchy(), object, [&](int id, const Primitive&) { out.push_back(id); });
    return out;
}

// Every front-side leaf of an object.
inline std::vector<const Node*> front_leaves(const Solver& s, int object) {
    std::vector<const Node*> out;
    for (int id : front_leaf_ids(s, object)) out.push_back(&s.hierarchy().nodes[size_t(id)]);
    return out;
}

// Whether one of the solver's warnings contains `what`.
inline bool has_warning(const Solver& s, const std::string& what) {
    for (const std::string& w : s.stats().warnings)
        if (w.find(what) != std::string::npos) return true;
    return false;
}

}  // namespace radiosity::testing
