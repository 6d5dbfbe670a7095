#include "radiosity/builtin_scenes.h"

namespace radiosity::scenes {

namespace {
// Appends quad q (counter-clockwise about its front) as an nu x nv grid of polygons.
void append_grid(ObjectDesc& o, const std::array<Vec3, 4>& q, int nu, int nv, Rgb rho, Rgb emission, bool two_sided) {
    const int base = int(o.vertices.size());
    for (int j = 0; j <= nv; ++j)
        for (int i = 0; i <= nu; ++i) {
            double u = double(i) / nu, v = double(j) / nv;
            o.vertices.push_back(q[0] * ((1 - u) * (1 - v)) + q[1] * (u * (1 - v)) + q[2] * (u * v) + q[3] * ((1 - u) * v));
        }
    for (int j = 0; j < nv; ++j)
        for (int i = 0; i < nu; ++i) {
            int a = base + j * (nu + 1) + i;
            o.loop_starts.push_back(int32_t(o.corner_verts.size()));
            o.loop_totals.push_back(4);
            o.corner_verts.insert(o.corner_verts.end(), {a, a + 1, a + nu + 2, a + nu + 1});
            o.reflectance.push_back(rho);
            o.emission.push_back(emission);
            o.two_sided.push_back(two_sided);
        }
}
}  // namespace

int add_grid(SceneDesc& s, const std::string& name, int cluster, const std::array<Vec3, 4>& q, int nu, int nv,
             Rgb rho, Rgb emission, bool two_sided) {
    ObjectDesc o;
    o.name = name;
    o.cluster = cluster;
    append_grid(o, q, nu, nv, rho, emission, two_sided);
    return s.add_object(std::move(o));
}

int add_box(SceneDesc& s, const std::string& name, int cluster, Vec3 lo, Vec3 hi, int n, Rgb rho, Rgb emission,
            bool inward, bool two_sided) {
    // One object, six grid faces; vertices are duplicated per face (sharp creases).
    ObjectDesc o;
    o.name = name;
    o.cluster = cluster;
    auto P = [&](int x, int y, int z) { return Vec3{x ? hi.x : lo.x, y ? hi.y : lo.y, z ? hi.z : lo.z}; };
    // Faces counter-clockwise seen from outside.
    const std::array<std::array<Vec3, 4>, 6> faces = {{
        {P(0, 0, 0), P(0, 1, 0), P(1, 1, 0), P(1, 0, 0)},  // -z
        {P(0, 0, 1), P(1, 0, 1), P(1, 1, 1), P(0, 1, 1)},  // +z
        {P(0, 0, 0), P(1, 0, 0), P(1, 0, 1), P(0, 0, 1)},  // -y
        {P(0, 1, 0), P(0, 1, 1), P(1, 1, 1), P(1, 1, 0)},  // +y
        {P(0, 0, 0), P(0, 0, 1), P(0, 1, 1), P(0, 1, 0)},  // -x
        {P(1, 0, 0), P(1, 1, 0), P(1, 1, 1), P(1, 0, 1)},  // +x
    }};
    for (auto q : faces) {
        if (inward) std::swap(q[1], q[3]);
        append_grid(o, q, n, n, rho, emission, two_sided);
    }
    return s.add_object(std::move(o));
}

SceneDesc lamp_under_ceiling(double gap) {
    SceneDesc s;
    add_box(s, "room", -1, {0, 0, 0}, {3, 3, 2.5}, 8, Rgb::all(0.7), Rgb{}, true, false);
    const double z = 2.5 - gap;
    add_grid(s, "lamp", -1, {Vec3{1.2, 1.2, z}, Vec3{1.2, 1.8, z}, Vec3{1.8, 1.8, z}, Vec3{1.8, 1.2, z}}, 1, 1, Rgb{},
             Rgb::all(10), true);
    return s;
}

SceneDesc furnace_cube(double rho, double e, int n, double size) {
    SceneDesc s;
    add_box(s, "room", -1, {0, 0, 0}, {size, size, size}, n, Rgb::all(rho), Rgb::all(e), true);
    return s;
}

SceneDesc furnace_room_with_box(double rho, double e, int n) {
    SceneDesc s;
    add_box(s, "room", -1, {0, 0, 0}, {3, 3, 2.5}, n, Rgb::all(rho), Rgb::all(e), true);
    int c = s.add_cluster("Furniture");
    // Lifted off the floor: an object resting on a surface is a contact case.
    add_box(s, "box", c, {1, 1, 0.1}, {2, 1.5, 1}, n, Rgb::all(rho), Rgb::all(e));
    return s;
}

SceneDesc cornell_box(int n) {
    SceneDesc s;
    const double k = 0.001;
    auto V = [k](double x, double y, double z) { return Vec3{x * k, y * k, z * k}; };
    const Rgb white{0.725, 0.71, 0.68}, red{0.63, 0.065, 0.05}, green{0.14, 0.45, 0.091};
    // Winding chosen so every normal points into the box.
    add_grid(s, "floor", -1, {V(552.8, 0, 0), V(0, 0, 0), V(0, 0, 559.2), V(549.6, 0, 559.2)}, n, n, white, {});
    add_grid(s, "ceiling", -1, {V(556, 548.8, 0), V(556, 548.8, 559.2), V(0, 548.8, 559.2), V(0, 548.8, 0)}, n, n,
             white, {});
    add_grid(s, "back", -1, {V(549.6, 0, 559.2), V(0, 0, 559.2), V(0, 548.8, 559.2), V(556, 548.8, 559.2)}, n, n,
             white, {});
    add_grid(s, "green", -1, {V(0, 0, 559.2), V(0, 0, 0), V(0, 548.8, 0), V(0, 548.8, 559.2)}, n, n, green, {});
    add_grid(s, "red", -1, {V(552.8, 0, 0), V(549.6, 0, 559.2), V(556, 548.8, 559.2), V(556, 548.8, 0)}, n, n, red, {});
    // Light 1 mm below the ceiling, facing down.
    add_grid(s, "light", -1, {V(343, 547.8, 227), V(343, 547.8, 332), V(213, 547.8, 332), V(213, 547.8, 227)}, 1, 1,
             Rgb{0, 0, 0}, Rgb{17, 12, 4});  // an Emission shader reflects nothing
    auto block = [&](const std::string& name, std::array<Vec3, 4> top) {
        int c = s.add_cluster(name);
        ObjectDesc o;
        o.name = name;
        o.cluster = c;
        for (auto& t : top) o.vertices.push_back(t);
        for (auto& t : top) o.vertices.push_back({t.x, 0, t.z});
        // top (0..3), sides (i, i+1) down to the floor
        auto face = [&](std::array<int, 4> f) {
            o.loop_starts.push_back(int32_t(o.corner_verts.size()));
            o.loop_totals.push_back(4);
            o.corner_verts.insert(o.corner_verts.end(), f.begin(), f.end());
            o.reflectance.push_back(white);
            o.emission.push_back({});
            o.two_sided.push_back(1);
        };
        face({0, 1, 2, 3});
        for (int i = 0; i < 4; ++i) {
            int j = (i + 1) % 4;
            face({i, 4 + i, 4 + j, j});
        }
        s.add_object(std::move(o));
    };
    block("short_block", {V(130, 165, 65), V(82, 165, 225), V(240, 165, 272), V(290, 165, 114)});
    block("tall_block", {V(423, 330, 247), V(265, 330, 296), V(314, 330, 456), V(472, 330, 406)});
    return s;
}

SceneDesc box_room(int n) {
    SceneDesc s;
    const Rgb wall{0.7, 0.7, 0.7};
    add_box(s, "room", -1, {0, 0, 0}, {300, 300, 250}, n, wall, {}, true);
    // Ceiling light 1 unit below the ceiling, facing down.
    add_grid(s, "light", -1, {Vec3{120, 120, 249}, Vec3{120, 180, 249}, Vec3{180, 180, 249}, Vec3{180, 120, 249}}, 1,
             1, Rgb::all(0.0), Rgb::all(12.0));
    int c1 = s.add_cluster("Box1");
    add_box(s, "Box1", c1, {114.4 - 30, 129.2 - 30, 0}, {114.4 + 30, 129.2 + 30, 100}, 2, Rgb{0.7, 0.3, 0.2}, {});
    int c2 = s.add_cluster("Box2");
    add_box(s, "Box2", c2, {200, 200, 0}, {260, 250, 60}, 2, Rgb{0.2, 0.4, 0.7}, {});
    return s;
}

SceneDesc point_light_box_on_floor(Vec3 light) {
    SceneDesc s;
    add_grid(s, "Floor", -1, {Vec3{-2, -2, 0}, Vec3{2, -2, 0}, Vec3{2, 2, 0}, Vec3{-2, 2, 0}}, 10, 10, Rgb::all(0.5), {});
    const int props = s.add_cluster("Props");
    add_box(s, "Box", props, {0.1, -0.2, 0.0}, {1.1, 0.8, 0.8}, 4, Rgb{0.7, 0.35, 0.2}, {});
    LightDesc l;
    l.name = "point";
    l.type = LightDesc::Type::Point;
    l.position = light;
    l.radius = 0.1;
    l.intensity = Rgb{1.0, 0.8, 0.6} * (200 / (4 * kPi));  // Blender: power x colour / 4 pi (W/sr)
    s.add_light(l);
    return s;
}

}  // namespace radiosity::scenes
