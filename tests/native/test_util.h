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

// The settings of the tests of moves, previews, additions and removals: MEDIUM with 32 rays a
// link (MEDIUM's refinement, cheaper links).
inline Settings dynamic_settings() {
    Settings st = Settings::preset("MEDIUM");
    st.rays_per_link = 32;
    return st;
}

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

// Room 300 x 300 x 250 with a ceiling light and two boxes (the paper's box room, coarse):
// the room is object 0, the light 1, the boxes 2 and 3, each in a collection of its own.
inline SceneDesc two_box_room(Vec3 box1_offset = {}, double light = 12.0) {
    SceneDesc s;
    scenes::add_box(s, "room", -1, {0, 0, 0}, {300, 300, 250}, 4, Rgb::all(0.7), {}, true);
    scenes::add_grid(s, "light", -1, {Vec3{120, 120, 249}, Vec3{120, 180, 249}, Vec3{180, 180, 249}, Vec3{180, 120, 249}}, 1, 1,
                     {}, Rgb::all(light), false);
    int c1 = s.add_cluster("Box1");
    scenes::add_box(s, "Box1", c1, Vec3{84.4, 99.2, 0} + box1_offset, Vec3{144.4, 159.2, 100} + box1_offset, 2,
                    Rgb{0.7, 0.3, 0.2}, {});
    int c2 = s.add_cluster("Box2");
    scenes::add_box(s, "Box2", c2, {200, 200, 0}, {260, 250, 60}, 2, Rgb{0.2, 0.4, 0.7}, {});
    return s;
}

// The add-on tests' small open scene: a 4 x 4 floor, a 1 x 1 emissive panel 2 above it facing
// down, and a box of 4 x 4 polygons a face on the floor (at `c`, its centre).
inline SceneDesc panel_over_box(Vec3 c) {
    SceneDesc s;
    scenes::add_grid(s, "Floor", -1, {Vec3{-2, -2, 0}, Vec3{2, -2, 0}, Vec3{2, 2, 0}, Vec3{-2, 2, 0}}, 10, 10,
                     Rgb::all(0.5), {});
    scenes::add_grid(s, "Panel", -1, {Vec3{-0.5, -0.5, 2}, Vec3{-0.5, 0.5, 2}, Vec3{0.5, 0.5, 2}, Vec3{0.5, -0.5, 2}}, 1,
                     1, Rgb::all(0.0), Rgb::all(10.0));
    const int props = s.add_cluster("Props");
    scenes::add_box(s, "Box", props, {c.x - 0.5, c.y - 0.5, 0}, {c.x + 0.5, c.y + 0.5, 0.8}, 4, Rgb{0.7, 0.35, 0.2}, {});
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

// A unit UV sphere of nu x nv faces (quads, triangles at the poles; outward) about c, in
// cluster `cluster`: a curved object of many normals and no facing summary.
inline ObjectDesc uv_sphere(const std::string& name, int cluster, int nu, int nv, Vec3 c = {}) {
    ObjectDesc o;
    o.name = name;
    o.cluster = cluster;
    for (int j = 0; j <= nv; ++j)
        for (int i = 0; i < nu; ++i) {
            const double th = kPi * j / nv, ph = 2 * kPi * i / nu;
            o.vertices.push_back(c + Vec3{std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th)});
        }
    for (int j = 0; j < nv; ++j)
        for (int i = 0; i < nu; ++i) {
            const int a = j * nu + i, b = j * nu + (i + 1) % nu;
            o.loop_starts.push_back(int32_t(o.corner_verts.size()));
            if (j == 0 || j == nv - 1) {  // the caps' triangles (counter-clockwise seen from outside)
                o.loop_totals.push_back(3);
                if (j == 0) o.corner_verts.insert(o.corner_verts.end(), {a, a + nu, b + nu});
                else o.corner_verts.insert(o.corner_verts.end(), {a, a + nu, b});
            } else {
                o.loop_totals.push_back(4);
                o.corner_verts.insert(o.corner_verts.end(), {a, a + nu, b + nu, b});
            }
            o.reflectance.push_back(Rgb::all(0.5));
            o.emission.push_back({});
            o.two_sided.push_back(0);
        }
    return o;
}

// Whether one of the solver's warnings contains `what`.
inline bool has_warning(const Solver& s, const std::string& what) {
    for (const std::string& w : s.stats().warnings)
        if (w.find(what) != std::string::npos) return true;
    return false;
}

}  // namespace radiosity::testing
