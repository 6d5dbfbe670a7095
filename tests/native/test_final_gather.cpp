// The output's final gather (final_gather.h): corner values at the corner points, against
// closed forms (the point-to-polygon irradiance of a lamp), the furnace, and contacts.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <initializer_list>
#include <string>

#include "radiosity/compare.h"
#include "test_util.h"

using namespace radiosity;
using namespace radiosity::testing;

namespace {

// Corner positions (world) of an object, one per corner.
std::vector<Vec3> corner_points(const SceneDesc& sc, int object) {
    const ObjectDesc& o = sc.objects()[size_t(object)];
    std::vector<Vec3> out;
    for (int32_t v : o.corner_verts) out.push_back(o.vertices[size_t(v)]);
    return out;
}

Poly square(double x0, double y0, double x1, double y1, double z, bool up) {
    return up ? quad({x0, y0, z}, {x1, y0, z}, {x1, y1, z}, {x0, y1, z})
              : quad({x0, y0, z}, {x0, y1, z}, {x1, y1, z}, {x1, y0, z});
}

}  // namespace

TEST(FinalGather, UnoccludedCornersMatchThePointToPolygonIrradiance) {
    // A black one-sided lamp (radiance 5) facing down over a gridded floor of reflectance 0.5,
    // nothing else: the light at a floor corner is rho x L x F(point -> lamp), F Lambert's
    // closed form. The leaf elements hold averages; the gather must give the point's value.
    SceneDesc sc;
    const double rho = 0.5, Le = 5.0;
    const int floor = scenes::add_grid(sc, "floor", -1, {Vec3{0, 0, 0}, Vec3{4, 0, 0}, Vec3{4, 4, 0}, Vec3{0, 4, 0}},
                                       9, 9, Rgb::all(rho), Rgb{}, false);
    scenes::add_grid(sc, "lamp", -1, {Vec3{1.3, 1.1, 1.5}, Vec3{1.3, 2.7, 1.5}, Vec3{2.9, 2.7, 1.5}, Vec3{2.9, 1.1, 1.5}},
                     1, 1, Rgb{}, Rgb::all(Le), false);
    const Poly lamp = square(1.3, 1.1, 2.9, 2.7, 1.5, false);
    for (const char* preset : {"DRAFT", "MEDIUM"}) {
        Solver s(sc, Settings::preset(preset));
        s.solve();
        const std::vector<float> c = s.corner_radiance(floor);
        const std::vector<Vec3> pts = corner_points(sc, floor);
        double worst = 0;
        for (size_t i = 0; i < pts.size(); ++i) {
            const double exact = rho * Le * point_polygon_form_factor(pts[i], {0, 0, 1}, lamp, lamp.normal());
            worst = std::max(worst, std::fabs(c[3 * i + 1] - exact) / exact);
        }
        std::printf("[ figure ] %s: worst floor corner vs the point-to-polygon closed form %.4f %%\n", preset, 100 * worst);
        EXPECT_LE(worst, 0.005) << preset;
    }
}

TEST(FinalGather, CeilingAboveATwoSidedLampMatchesTheClosedForm) {
    // A two-sided lamp 1 mm under a 12 x 12 gridded ceiling (reflectance 0.5), not aligned with
    // the grid; nothing else. A leaf straddling the lamp's edge averages light and dark (the
    // issue's Cornell box read 4.0 where Cycles reads 7.85); the corners must read
    // rho x L x F(point -> lamp's upper face) within 2 %.
    SceneDesc sc;
    const double rho = 0.5, Le = 10.0, z = 2.0;
    const int ceiling = scenes::add_grid(sc, "ceiling", -1, {Vec3{0, 0, z}, Vec3{0, 3, z}, Vec3{3, 3, z}, Vec3{3, 0, z}},
                                         12, 12, Rgb::all(rho), Rgb{}, false);
    const double zl = z - 0.001;
    scenes::add_grid(sc, "lamp", -1, {Vec3{1.1, 0.95, zl}, Vec3{1.9, 0.95, zl}, Vec3{1.9, 2.05, zl}, Vec3{1.1, 2.05, zl}},
                     1, 1, Rgb{}, Rgb::all(Le), true);
    const Poly lamp_up = square(1.1, 0.95, 1.9, 2.05, zl, true);
    Solver s(sc, Settings::preset("MEDIUM"));
    s.solve();
    const std::vector<float> c = s.corner_radiance(ceiling);
    const std::vector<Vec3> pts = corner_points(sc, ceiling);
    double worst = 0;
    int above = 0;
    for (size_t i = 0; i < pts.size(); ++i) {
        const Vec3& p = pts[i];
        if (p.x < 1.1 || p.x > 1.9 || p.y < 0.95 || p.y > 2.05) continue;
        ++above;
        const double exact = rho * Le * point_polygon_form_factor(p, {0, 0, -1}, lamp_up, lamp_up.normal());
        worst = std::max(worst, std::fabs(c[3 * i] - exact) / exact);
    }
    std::printf("[ figure ] ceiling corners above the lamp: %d, worst %.4f %% from the closed form\n", above, 100 * worst);
    ASSERT_GT(above, 8);
    EXPECT_LE(worst, 0.02);
}

TEST(FinalGather, FurnaceStaysExact) {
    // Closed room, uniform emission and reflectance: every corner B = E / (1 - rho). The
    // gather's couplings at an enclosed point must close to 1 as the leaves' do.
    for (const char* preset : {"DRAFT", "MEDIUM"}) {
        const double rho = 0.5, e = 1.0, exact = e / (1 - rho);
        Solver s(scenes::furnace_room_with_box(rho, e, 4), Settings::preset(preset));
        s.solve();
        double worst = 0;
        for (size_t o = 0; o < s.scene().objects().size(); ++o)
            for (float v : s.corner_radiance(int(o))) worst = std::max(worst, std::fabs(v - exact) / exact);
        std::printf("[ figure ] furnace room with a box, %s: worst corner %.4f %%\n", preset, 100 * worst);
        EXPECT_LE(worst, 0.001) << preset;
    }
}

TEST(FinalGather, FurnaceStaysExactWithAPolygonThatCastsNoShadow) {
    // The furnace room with a dark area light (a polygon that casts no shadow, as a Blender
    // area light in Cycles) hung 10 cm under its ceiling: rays pass through it, so whatever
    // sees it also sees the ceiling behind it and its coupling comes on top of a full 1. The
    // closure must not count it: taking that excess from the room's own couplings read the
    // walls beside a bright area light 5 % dark (bench/tradeoff's lights room). Here it
    // sends nothing, so every corner keeps B = E / (1 - rho).
    for (const char* preset : {"DRAFT", "MEDIUM"}) {
        const double rho = 0.5, e = 1.0, exact = e / (1 - rho);
        SceneDesc sc = scenes::furnace_room_with_box(rho, e, 4);
        ObjectDesc lamp;
        lamp.name = "area";
        lamp.vertices = {{1.1, 1.1, 2.4}, {1.1, 1.9, 2.4}, {1.9, 1.9, 2.4}, {1.9, 1.1, 2.4}};  // facing down
        lamp.loop_starts = {0};
        lamp.loop_totals = {4};
        lamp.corner_verts = {0, 1, 2, 3};
        lamp.reflectance = {Rgb{}};
        lamp.emission = {Rgb{}};
        lamp.two_sided = {0};
        lamp.occluder = false;
        const int area = sc.add_object(lamp);
        Solver s(sc, Settings::preset(preset));
        s.solve();
        double worst = 0;
        for (size_t o = 0; o < s.scene().objects().size(); ++o) {
            if (int(o) == area) continue;
            for (float v : s.corner_radiance(int(o))) worst = std::max(worst, std::fabs(v - exact) / exact);
        }
        std::printf("[ figure ] furnace room with a box and a dark area light, %s: worst corner %.4f %%\n", preset,
                    100 * worst);
        EXPECT_LE(worst, 0.001) << preset;
    }
}

TEST(FinalGather, CornersUnderABoxOnAGriddedFloorAreUnlit) {
    // A box standing on a gridded floor whose vertices lie under it and on its footprint's
    // edge: corners of floor faces under the box read 0 (Cycles: unlit), corners of faces
    // beside it are lit, and so are the box's side corners at its foot.
    SceneDesc sc;
    const int floor = scenes::add_grid(sc, "floor", -1, {Vec3{0, 0, 0}, Vec3{4, 0, 0}, Vec3{4, 4, 0}, Vec3{0, 4, 0}},
                                       8, 8, Rgb::all(0.5), Rgb{}, false);
    const int box = scenes::add_box(sc, "box", -1, {1.5, 1.5, 0}, {2.5, 2.5, 1}, 2, Rgb::all(0.5), Rgb{});
    scenes::add_grid(sc, "lamp", -1, {Vec3{1, 1, 3}, Vec3{1, 3, 3}, Vec3{3, 3, 3}, Vec3{3, 1, 3}}, 1, 1, Rgb{},
                     Rgb::all(10), false);
    Solver s(sc, Settings::preset("MEDIUM"));
    s.solve();
    const ObjectDesc& fo = sc.objects()[size_t(floor)];
    const std::vector<float> c = s.corner_radiance(floor);
    int under = 0, lit_edge = 0, dark_edge = 0;
    for (size_t f = 0; f < fo.polygon_count(); ++f) {
        Vec3 centre;
        for (int k = 0; k < fo.loop_totals[f]; ++k) centre += fo.vertices[size_t(fo.corner_verts[size_t(fo.loop_starts[f] + k)])] / fo.loop_totals[f];
        const bool face_under = centre.x > 1.5 && centre.x < 2.5 && centre.y > 1.5 && centre.y < 2.5;
        for (int k = 0; k < fo.loop_totals[f]; ++k) {
            const size_t ci = size_t(fo.loop_starts[f] + k);
            const Vec3 p = fo.vertices[size_t(fo.corner_verts[ci])];
            const bool on_edge = p.x >= 1.5 && p.x <= 2.5 && p.y >= 1.5 && p.y <= 2.5 &&
                                 (p.x == 1.5 || p.x == 2.5 || p.y == 1.5 || p.y == 2.5);
            if (face_under) {
                ++under;
                EXPECT_EQ(c[3 * ci], 0.f) << "floor corner under the box at " << p.x << "," << p.y;
            } else if (on_edge) {
                (c[3 * ci] > 0.01f ? lit_edge : dark_edge)++;
            }
        }
    }
    EXPECT_GT(under, 8);
    EXPECT_GT(lit_edge, 8);
    EXPECT_EQ(dark_edge, 0);
    // The box's bottom face lies on the floor: unlit; its sides' corners at the foot see the
    // floor and the room.
    const ObjectDesc& bo = sc.objects()[size_t(box)];
    const std::vector<float> b = s.corner_radiance(box);
    double side_foot = 0;
    int n_side = 0;
    for (size_t f = 0; f < bo.polygon_count(); ++f) {
        double zmax = 0;
        for (int k = 0; k < bo.loop_totals[f]; ++k) zmax = std::max(zmax, bo.vertices[size_t(bo.corner_verts[size_t(bo.loop_starts[f] + k)])].z);
        for (int k = 0; k < bo.loop_totals[f]; ++k) {
            const size_t ci = size_t(bo.loop_starts[f] + k);
            if (zmax == 0) EXPECT_EQ(b[3 * ci], 0.f) << "bottom corner";
            else if (bo.vertices[size_t(bo.corner_verts[ci])].z == 0) side_foot += b[3 * ci], ++n_side;
        }
    }
    ASSERT_GT(n_side, 0);
    EXPECT_GT(side_foot / n_side, 0.01);
}

TEST(FinalGather, DimmingTheLampScalesEveryCorner) {
    // An emission change is an update; the corners it outputs are the gather's (not the
    // leaves') and follow the light linearly: dimming the lamp to 30 % scales every corner.
    SceneDesc sc;
    const int floor = scenes::add_grid(sc, "floor", -1, {Vec3{0, 0, 0}, Vec3{4, 0, 0}, Vec3{4, 4, 0}, Vec3{0, 4, 0}},
                                       6, 6, Rgb::all(0.5), Rgb{}, false);
    const int lamp = scenes::add_grid(sc, "lamp", -1, {Vec3{1, 1, 2}, Vec3{1, 3, 2}, Vec3{3, 3, 2}, Vec3{3, 1, 2}}, 1, 1,
                                      Rgb{}, Rgb::all(10), false);
    Solver s(sc, Settings::preset("MEDIUM"));
    s.solve();
    const std::vector<float> before = s.corner_radiance(floor);
    s.set_emission(lamp, {Rgb::all(3)});
    s.update();
    const std::vector<float> after = s.corner_radiance(floor);
    ASSERT_EQ(before.size(), after.size());
    for (size_t i = 0; i < before.size(); ++i) EXPECT_NEAR(after[i], 0.3f * before[i], 0.01f * before[i] + 1e-7f);
}

namespace {

// A block open at the bottom (top and four sides, faces outward) standing on the floor, as
// the Cornell box's blocks are: the floor under it is inside a closed solid.
void add_bottomless_block(SceneDesc& sc, Vec3 lo, Vec3 hi, bool two_sided, int cluster = -1) {
    const Rgb rho = Rgb::all(0.5);
    scenes::add_grid(sc, "top", cluster, {Vec3{lo.x, lo.y, hi.z}, Vec3{hi.x, lo.y, hi.z}, Vec3{hi.x, hi.y, hi.z}, Vec3{lo.x, hi.y, hi.z}},
                     2, 2, rho, Rgb{}, two_sided);
    scenes::add_grid(sc, "south", cluster, {Vec3{lo.x, lo.y, lo.z}, Vec3{hi.x, lo.y, lo.z}, Vec3{hi.x, lo.y, hi.z}, Vec3{lo.x, lo.y, hi.z}},
                     2, 2, rho, Rgb{}, two_sided);
    scenes::add_grid(sc, "north", cluster, {Vec3{hi.x, hi.y, lo.z}, Vec3{lo.x, hi.y, lo.z}, Vec3{lo.x, hi.y, hi.z}, Vec3{hi.x, hi.y, hi.z}},
                     2, 2, rho, Rgb{}, two_sided);
    scenes::add_grid(sc, "west", cluster, {Vec3{lo.x, hi.y, lo.z}, Vec3{lo.x, lo.y, lo.z}, Vec3{lo.x, lo.y, hi.z}, Vec3{lo.x, hi.y, hi.z}},
                     2, 2, rho, Rgb{}, two_sided);
    scenes::add_grid(sc, "east", cluster, {Vec3{hi.x, lo.y, lo.z}, Vec3{hi.x, hi.y, lo.z}, Vec3{hi.x, hi.y, hi.z}, Vec3{hi.x, lo.y, hi.z}},
                     2, 2, rho, Rgb{}, two_sided);
}

// Floor corners whose point lies strictly inside the rectangle lo-hi (x, y), and the others.
struct Split {
    double inside_max = 0, outside_mean = 0;
    int inside = 0, outside = 0;
};
Split split_floor(const SceneDesc& sc, int floor, const std::vector<float>& c, Vec3 lo, Vec3 hi) {
    const ObjectDesc& fo = sc.objects()[size_t(floor)];
    Split r;
    for (size_t f = 0; f < fo.polygon_count(); ++f) {
        Vec3 centre;
        for (int k = 0; k < fo.loop_totals[f]; ++k) centre += fo.vertices[size_t(fo.corner_verts[size_t(fo.loop_starts[f] + k)])] / fo.loop_totals[f];
        for (int k = 0; k < fo.loop_totals[f]; ++k) {
            const size_t ci = size_t(fo.loop_starts[f] + k);
            const Vec3 p = fo.vertices[size_t(fo.corner_verts[ci])];
            // The corner's point lies a hair from p toward the face's centre.
            const Vec3 q = p + (centre - p) * 1e-3;
            const bool in = q.x > lo.x && q.x < hi.x && q.y > lo.y && q.y < hi.y;
            if (in) {
                r.inside_max = std::max(r.inside_max, double(c[3 * ci + 1]));
                ++r.inside;
            } else {
                r.outside_mean += c[3 * ci + 1];
                ++r.outside;
            }
        }
    }
    if (r.outside > 0) r.outside_mean /= r.outside;
    return r;
}

}  // namespace

TEST(FinalGather, FloorInsideABottomlessBlockIsUnlit) {
    // The Cornell box's blocks have no bottom: the floor under one is inside a closed solid,
    // and Cycles reads it 0. The floor's faces straddle the block's walls (0.5 m grid, block
    // from 1.3 to 2.7 m), so its leaves carry the room's light inside and the block's inner
    // faces glow with it: the Cornell box read 7 % of the mean there, 98 % of its error.
    for (bool two_sided : {false, true}) {
        SceneDesc sc;
        const int floor = scenes::add_grid(sc, "floor", -1, {Vec3{0, 0, 0}, Vec3{4, 0, 0}, Vec3{4, 4, 0}, Vec3{0, 4, 0}},
                                           8, 8, Rgb::all(0.5), Rgb{}, false);
        const Vec3 lo{1.3, 1.3, 0}, hi{2.7, 2.7, 1};
        add_bottomless_block(sc, lo, hi, two_sided);
        scenes::add_grid(sc, "lamp", -1, {Vec3{0.5, 0.5, 3}, Vec3{0.5, 3.5, 3}, Vec3{3.5, 3.5, 3}, Vec3{3.5, 0.5, 3}}, 1, 1,
                         Rgb{}, Rgb::all(10), false);
        for (bool rule : {true, false}) {
            Settings st = Settings::preset("MEDIUM");
            st.gather_sealed_solids = rule;
            Solver s(sc, st);
            s.solve();
            const Split r = split_floor(sc, floor, s.corner_radiance(floor), lo, hi);
            std::printf("[ figure ] two-sided %d, rule %d: floor inside the block max %.5f (%d corners), outside mean %.4f, "
                        "sealed points %lld\n", int(two_sided), int(rule), r.inside_max, r.inside, r.outside_mean,
                        (long long)s.stats().gather_sealed);
            ASSERT_GT(r.inside, 8);
            ASSERT_GT(r.outside_mean, 0.1);
            if (rule) {
                EXPECT_EQ(r.inside_max, 0.0);
                EXPECT_GT(s.stats().gather_sealed, 0);
            } else if (two_sided) {
                // Without it the leak shows (two-sided, as the add-on hands Blender's meshes
                // over: the block's inner faces are surfaces that can hold light; one-sided,
                // they are none and nothing leaks): the test tells the rule from its absence.
                EXPECT_GT(r.inside_max, 1e-3 * r.outside_mean);
            }
        }
    }
}

TEST(FinalGather, CornersInsideASolidReadNothingThoughOtherObjectsAreInThere) {
    // A box B sunk half into a closed box A (an eye in a head) and a box C floating inside A.
    // No light enters A, so every corner inside it reads 0 in Cycles. From inside, B's corners
    // see A's backs and C's fronts, C's corners A's backs and B's fronts: a point is inside a
    // solid when each ray meets a back or a front that is itself inside one.
    SceneDesc sc;
    const Rgb rho = Rgb::all(0.5);
    scenes::add_grid(sc, "floor", -1, {Vec3{0, 0, 0}, Vec3{4, 0, 0}, Vec3{4, 4, 0}, Vec3{0, 4, 0}}, 8, 8, rho, Rgb{}, true);
    scenes::add_box(sc, "A", -1, Vec3{1, 1, 0}, Vec3{3, 3, 1}, 4, rho, Rgb{});
    const int b = scenes::add_box(sc, "B", -1, Vec3{1.6, 1.6, 0.75}, Vec3{2.1, 2.1, 1.25}, 5, rho, Rgb{});
    const int c = scenes::add_box(sc, "C", -1, Vec3{2.3, 2.3, 0.3}, Vec3{2.7, 2.7, 0.5}, 2, rho, Rgb{});
    scenes::add_grid(sc, "lamp", -1, {Vec3{0.5, 0.5, 3}, Vec3{0.5, 3.5, 3}, Vec3{3.5, 3.5, 3}, Vec3{3.5, 0.5, 3}}, 1, 1,
                     Rgb{}, Rgb::all(10), false);
    for (uint64_t seed : {1u, 7u}) {
        Settings st = Settings::preset("MEDIUM");
        st.seed = seed;
        Solver s(sc, st);
        s.solve();
        double inside_max = 0, outside_sum = 0;
        int inside = 0, outside = 0;
        std::vector<double> inside_values;
        for (int obj : {b, c}) {
            const ObjectDesc& o = sc.objects()[size_t(obj)];
            const std::vector<float> v = s.corner_radiance(obj);
            for (size_t k = 0; k < o.corner_verts.size(); ++k) {
                const double g = v[3 * k + 1];
                ASSERT_TRUE(std::isfinite(g));
                if (obj == c || o.vertices[size_t(o.corner_verts[k])].z < 1.0 - 1e-9) {
                    inside_max = std::max(inside_max, g);
                    inside_values.push_back(g);
                    ++inside;
                } else {
                    outside_sum += g;
                    ++outside;
                }
            }
        }
        const double mean = outside_sum / std::max(outside, 1);
        const long lit = std::count_if(inside_values.begin(), inside_values.end(), [&](double g) { return g > 1e-6 * mean; });
        std::printf("[ figure ] seed %llu: %d corners inside A, %ld of them lit, max %.5f; %d outside, mean %.4f; "
                    "sealed points %lld\n", (unsigned long long)seed, inside, lit, inside_max, outside, mean,
                    (long long)s.stats().gather_sealed);
        ASSERT_GT(inside, 100);
        ASSERT_GT(mean, 0.05);
        EXPECT_LE(lit, inside / 50);
        EXPECT_LT(inside_max, 1e-3 * mean);
    }
}

TEST(FinalGather, ALampInsideAClosedBoxKeepsTheBoxLitInside) {
    // A point light inside a closed box standing on the floor: the inside of that solid is lit
    // (the floor under the box reads what lies beyond its bottom, as in Cycles), so the
    // sealed rule must stand down. And over a one-sided lamp hung under a ceiling, the ceiling
    // sees the lamp's back everywhere: one plane, not a solid, never sealed.
    SceneDesc sc;
    const int floor = scenes::add_grid(sc, "floor", -1, {Vec3{0, 0, 0}, Vec3{4, 0, 0}, Vec3{4, 4, 0}, Vec3{0, 4, 0}},
                                       8, 8, Rgb::all(0.5), Rgb{}, false);
    scenes::add_box(sc, "box", -1, {1.3, 1.3, 0}, {2.7, 2.7, 1}, 2, Rgb::all(0.5), Rgb{});
    scenes::add_grid(sc, "ceiling", -1, {Vec3{0, 0, 3}, Vec3{0, 4, 3}, Vec3{4, 4, 3}, Vec3{4, 0, 3}}, 8, 8, Rgb::all(0.5),
                     Rgb{}, false);
    scenes::add_grid(sc, "lamp", -1, {Vec3{1.4, 1.4, 2.999}, Vec3{1.4, 2.6, 2.999}, Vec3{2.6, 2.6, 2.999}, Vec3{2.6, 1.4, 2.999}},
                     1, 1, Rgb{}, Rgb::all(10), false);
    {
        Solver s(sc, Settings::preset("DRAFT"));
        s.solve();
        std::printf("[ figure ] lamp outside the box: sealed points %lld\n", (long long)s.stats().gather_sealed);
        // Only the floor under the box is sealed (its corners covered by the box's bottom).
        const Split r = split_floor(sc, floor, s.corner_radiance(floor), {1.3, 1.3, 0}, {2.7, 2.7, 1});
        EXPECT_GT(s.stats().gather_sealed, 0);
        EXPECT_EQ(r.inside_max, 0.0);
    }
    sc.add_light(point_light({2.0, 2.0, 0.5}, 50, 0.05));
    Solver s(sc, Settings::preset("DRAFT"));
    s.solve();
    std::printf("[ figure ] a lamp inside the box too: sealed points %lld\n", (long long)s.stats().gather_sealed);
    EXPECT_EQ(s.stats().gather_sealed, 0);
}

TEST(FinalGather, MovingABottomlessBlockSealsTheFloorItComesToCover) {
    // The sealed state of a point is found again by every update: the block moved 0.8 m across
    // the floor darkens the floor it now stands on and frees the floor it left, and the update
    // equals a full solve of the moved scene.
    const Vec3 lo{1.3, 1.3, 0}, hi{2.2, 2.2, 1}, to{0.8, 0.4, 0};
    auto scene = [&](Vec3 offset) {
        SceneDesc sc;
        scenes::add_grid(sc, "floor", -1, {Vec3{0, 0, 0}, Vec3{4, 0, 0}, Vec3{4, 4, 0}, Vec3{0, 4, 0}}, 8, 8, Rgb::all(0.5),
                         Rgb{}, false);
        add_bottomless_block(sc, lo + offset, hi + offset, true, sc.add_cluster("block"));
        scenes::add_grid(sc, "lamp", -1, {Vec3{0.5, 0.5, 3}, Vec3{0.5, 3.5, 3}, Vec3{3.5, 3.5, 3}, Vec3{3.5, 0.5, 3}}, 1, 1,
                         Rgb{}, Rgb::all(10), false);
        return sc;
    };
    const SceneDesc before = scene({}), after = scene(to);
    Solver inc(before, Settings::preset("MEDIUM"));
    inc.solve();
    for (int o = 1; o <= 5; ++o) inc.move_object(o, translation(to));
    inc.update();
    Solver full(after, Settings::preset("MEDIUM"));
    full.solve();
    const Split now = split_floor(after, 0, inc.corner_radiance(0), lo + to, hi + to);
    const Split was = split_floor(after, 0, inc.corner_radiance(0), lo, hi);
    const double e = nrmse(inc.all_corner_radiance(), full.all_corner_radiance());
    std::printf("[ figure ] block moved: floor inside its new footprint max %.5f (%d corners), inside the old one "
                "max %.4f; update vs full NRMSE %.4f; sealed points %lld (full %lld)\n", now.inside_max, now.inside,
                was.inside_max, e, (long long)inc.stats().gather_sealed, (long long)full.stats().gather_sealed);
    EXPECT_TRUE(inc.stats().mode_incremental);
    ASSERT_GT(now.inside, 8);
    EXPECT_EQ(now.inside_max, 0.0);
    EXPECT_GT(was.inside_max, 0.1);  // the floor the block left is lit again
    EXPECT_EQ(inc.stats().gather_sealed, full.stats().gather_sealed);
    EXPECT_LE(e, 0.005);
}

namespace {

// The exact coupling of the point x (normal n) to the front faces of `objects`: the sum of
// their leaves' point-to-polygon form factors, what a cluster's sampled estimates must match.
double exact_coupling(const Solver& s, std::initializer_list<int> objects, const Vec3& x, const Vec3& n) {
    double exact = 0;
    for (const int o : objects)
        for (const Node* leaf : front_leaves(s, o)) exact += point_polygon_form_factor(x, n, leaf->poly, leaf->normal);
    return exact;
}

// Over `trials` 8-ray estimates (seeds seed0, seed0 + 1, ...) of the coupling from cluster src
// to the point x (normal n, receiving leaf rcv): the worst and the mean estimate over the exact
// coupling to the front faces of `objects` (the cluster's surfaces).
struct Estimates {
    double exact = 0, worst = 0, mean = 0;
};
Estimates coupling_estimates(const Solver& s, int src, std::initializer_list<int> objects, const Vec3& x, const Vec3& n,
                             int rcv, int trials, uint64_t seed0) {
    Estimates e;
    e.exact = exact_coupling(s, objects, x, n);
    double sum = 0;
    std::vector<std::pair<int, float>> samples;
    for (int k = 0; k < trials; ++k) {
        PointRayStream rays(s.visibility());
        samples.clear();
        const PointTransfer t = point_transfer(s.hierarchy(), rays, src, x, n, rcv, 8, seed0 + uint64_t(k), samples);
        e.worst = std::max(e.worst, t.F_unoccluded / e.exact);
        sum += t.F_unoccluded;
    }
    e.mean = sum / trials / e.exact;
    return e;
}

// The estimates of `what` unbiased (mean within 2 % of exact) and bounded (none over `worst`
// times exact), with the figures printed.
void expect_unbiased(const Estimates& e, const char* what, double worst) {
    ASSERT_GT(e.exact, 0.0);
    std::printf("[ figure ] 8-ray estimates of %s: worst %.3f x exact, mean %.4f x exact\n", what, e.worst, e.mean);
    EXPECT_NEAR(e.mean, 1.0, 0.02);
    EXPECT_LE(e.worst, worst);
}

// The first front leaf of the probe object (the receiving leaf of the point transfers), or -1.
int probe_leaf(const Solver& s, int probe) {
    const std::vector<int> leaves = front_leaf_ids(s, probe);
    return leaves.empty() ? -1 : leaves[0];
}

// A gridded floor plate (normal +z) and a gridded wall behind it (normal +x), grid x grid
// faces each, in one collection, and a small probe quad (its corners, facing -x) to receive.
struct PlateAndWall {
    SceneDesc scene;
    int plate = -1, wall = -1, probe = -1;
};
PlateAndWall plate_and_wall(int grid, const std::array<Vec3, 4>& probe) {
    PlateAndWall p;
    const int cl = p.scene.add_cluster("corner");
    p.plate = scenes::add_grid(p.scene, "plate", cl, {Vec3{-0.5, -0.5, 0}, Vec3{0.5, -0.5, 0}, Vec3{0.5, 0.5, 0}, Vec3{-0.5, 0.5, 0}},
                               grid, grid, Rgb::all(0.5), Rgb{}, false);
    p.wall = scenes::add_grid(p.scene, "wall", cl, {Vec3{-0.5, -0.5, 0}, Vec3{-0.5, 0.5, 0}, Vec3{-0.5, 0.5, 1}, Vec3{-0.5, -0.5, 1}},
                              grid, grid, Rgb::all(0.5), Rgb{}, false);
    p.probe = scenes::add_grid(p.scene, "probe", -1, {probe[0], probe[1], probe[2], probe[3]}, 1, 1, Rgb::all(0.5), Rgb{}, false);
    return p;
}

// The live cluster holding exactly `surfaces` surfaces (-1: none).
int cluster_of(const Hierarchy& h, int surfaces) {
    for (size_t i = 0; i < h.nodes.size(); ++i)
        if (h.nodes[i].is_cluster() && !h.nodes[i].dead && h.nodes[i].surf_end - h.nodes[i].surf_begin == surfaces)
            return int(i);
    return -1;
}

}  // namespace

TEST(FinalGather, ClusterSenderWeightsStayBoundedForAFaceEdgeOnToTheCentre) {
    // A cluster of a gridded floor plate (normal +z) and a gridded wall behind it (normal +x),
    // seen from a point 6 m away along +x, 2 cm above the cluster's centre: the plate is nearly
    // edge-on to the direction from the centre (cos 0.004) yet faces the point (cos 0.07). Drawn
    // by the projected area toward the centre alone, a ray on the plate weighed ~20 times a ray
    // on the wall, and an 8-ray estimate that drew one read 3x the whole coupling (the full
    // room's cabinet vertex, transfer.cpp FacingSampler). Every 8-ray estimate must stay
    // within 1.6x the exact coupling, and their mean within 2 % of it.
    const PlateAndWall pw = plate_and_wall(4, {Vec3{6, 0.1, 0.3}, Vec3{6, -0.1, 0.3}, Vec3{6, -0.1, 0.6}, Vec3{6, 0.1, 0.6}});
    const int plate = pw.plate, wall = pw.wall, probe = pw.probe;
    Solver s(pw.scene, Settings::preset("DRAFT"));
    s.solve();
    const Hierarchy& h = s.hierarchy();
    const int src = cluster_of(h, 32);
    ASSERT_GE(src, 0) << "no cluster of the plate's and the wall's 32 faces";
    const Node& P = h.nodes[size_t(src)];
    const int rcv = probe_leaf(s, probe);
    ASSERT_GE(rcv, 0);
    // The point (internal frame), 2 cm (world) above the cluster's centre, facing the cluster.
    const Vec3 c = P.center * h.unit + h.origin;  // world
    const Vec3 x = h.to_internal(Vec3{6.0, c.y, c.z + 0.02});
    ASSERT_GT(length(x - P.center), 2.0 * P.radius);
    const Vec3 n{-1, 0, 0};
    expect_unbiased(coupling_estimates(s, src, {plate, wall}, x, n, rcv, 400, 1000), "the cluster's coupling", 1.6);
}

TEST(FinalGather, AnExcessAtAPointIsTakenFromItsSampledCouplings) {
    // A seat point in a closed room (full_room.blend, HIGH): own couplings 0.896, all sampled
    // (cluster senders); inherited 0.138, of which the lamp's exact element links 0.035 and
    // sampled 0.103. The couplings after the closure sum to 1 and the exact ones keep theirs.
    const double own = 0.896, inherited = 0.138, s_own = 0.896, s_inh = 0.103;
    const ClosureFactors c = point_closure_factors(own, inherited, s_own, s_inh);
    EXPECT_NEAR(own * c.c_own + inherited * c.c_inherited, 1.0, 1e-12);
    EXPECT_EQ(c.fill, 0.0);
    const double exact_inh = inherited - s_inh;
    const double k = c.c_own;  // the own couplings are all sampled here: their scale is the sampled parts
    EXPECT_NEAR(inherited * c.c_inherited, exact_inh + s_inh * k, 1e-12) << "sampled parts scaled alike";
    EXPECT_GT(inherited * c.c_inherited, exact_inh) << "the exact lamp links keep their coupling";
    // The leaf's rule would have cut every inherited coupling, the lamp's with them, by 25 %.
    EXPECT_NEAR(closure_factors(own, inherited).c_inherited, 0.104 / 0.138, 1e-9);
    // Sampled couplings too small to hold the excess: every coupling scaled alike to sum 1.
    const ClosureFactors d = point_closure_factors(0.7, 0.5, 0.05, 0.05);
    EXPECT_NEAR(0.7 * d.c_own + 0.5 * d.c_inherited, 1.0, 1e-12);
    EXPECT_DOUBLE_EQ(d.c_own, d.c_inherited);
    // A shortfall, and sums far off 1, as at a leaf.
    const ClosureFactors e = point_closure_factors(0.6, 0.3, 0.6, 0.3), el = closure_factors(0.6, 0.3);
    EXPECT_EQ(e.fill, el.fill);
    EXPECT_EQ(e.c_own, 1.0);
    const ClosureFactors g = point_closure_factors(3.0, 2.0, 3.0, 2.0);
    EXPECT_EQ(g.c_own, 1.0);
    EXPECT_EQ(g.c_inherited, 1.0);
}

namespace {
// A UV sphere of nu x nv faces (a subdivided cushion: many normals, no facing summary) in its
// own collection, read from a point outside it: the mean of 8-ray estimates of its coupling
// must match the exact one (the sum of the point-to-polygon form factors of its faces), and no
// estimate may run away. `what` names the sampler the sphere's size selects.
void expect_sphere_drawn_unbiased(int nu, int nv, int min_surfaces, int max_surfaces, const char* what) {
    SceneDesc sc;
    const int cl = sc.add_cluster("cushion");
    sc.add_object(uv_sphere("sphere", cl, nu, nv));
    const int probe = scenes::add_grid(sc, "probe", -1, {Vec3{4, 0.1, -0.1}, Vec3{4, -0.1, -0.1}, Vec3{4, -0.1, 0.1}, Vec3{4, 0.1, 0.1}},
                                       1, 1, Rgb::all(0.5), Rgb{}, false);
    sc.add_light([] {
        LightDesc l;
        l.name = "sun";
        l.type = LightDesc::Type::Sun;
        l.direction = normalize(Vec3{-1, 0.2, -0.5});
        l.intensity = Rgb::all(1.0);
        return l;
    }());
    Solver s(sc, Settings::preset("DRAFT"));
    s.solve();
    const Hierarchy& h = s.hierarchy();
    int src = -1;
    for (size_t i = 0; i < h.nodes.size(); ++i)
        if (h.nodes[i].is_cluster() && !h.nodes[i].dead && h.nodes[i].object == 0 &&
            (src < 0 || h.nodes[i].surf_end - h.nodes[i].surf_begin > h.nodes[size_t(src)].surf_end - h.nodes[size_t(src)].surf_begin))
            src = int(i);
    ASSERT_GE(src, 0);
    const Node& P = h.nodes[size_t(src)];
    ASSERT_GT(P.surf_end - P.surf_begin, min_surfaces) << what;
    ASSERT_LE(P.surf_end - P.surf_begin, max_surfaces) << what;
    ASSERT_FALSE(h.has_facing_summary(src));
    const int rcv = probe_leaf(s, probe);
    ASSERT_GE(rcv, 0);
    const Vec3 x = h.to_internal(Vec3{4, 0.3, 0.2});
    ASSERT_GT(length(x - P.center), 2.0 * P.radius);
    const Vec3 n = normalize(Vec3{-1, -0.1, -0.05});
    expect_unbiased(coupling_estimates(s, src, {0}, x, n, rcv, 2000, 7000), what, 2.0);
}
}  // namespace

TEST(FinalGather, LargeClustersOfManyNormalsAreDrawnDownTheirTreeUnbiased) {
    // Over 256 faces: drawn down the cluster tree (TreeSampler), O(depth) a ray.
    expect_sphere_drawn_unbiased(24, 16, 256, 1 << 20, "a 384-face sphere cluster's coupling");
}

TEST(FinalGather, MidSizeClustersAreDrawnFromATableOfTheirFacesUnbiased) {
    // Up to 256 faces: drawn from a table of every face by facing area (FacingSampler), with
    // the gather's floor on the cosine.
    expect_sphere_drawn_unbiased(16, 10, 12, 256, "a 160-face sphere cluster's coupling");
}

TEST(FinalGather, LargeClustersOfFewNormalsAreDrawnByRejectionUnbiased) {
    // A gridded floor plate (normal +z) and a gridded wall (normal +x), 578 faces in one
    // collection: a cluster of two normals, drawn by area and kept with probability cos over
    // the largest cos of its normals. Seen from a point far off to the side and a little above,
    // the plate is almost edge-on (its draws kept one in five), the wall at 60 degrees. The mean
    // of 8-ray estimates must match the exact coupling, and no estimate may run away.
    const PlateAndWall pw = plate_and_wall(17, {Vec3{3, 5.3, 0.1}, Vec3{3, 5.1, 0.1}, Vec3{3, 5.1, 0.3}, Vec3{3, 5.3, 0.3}});
    const int plate = pw.plate, wall = pw.wall, probe = pw.probe;
    Solver s(pw.scene, Settings::preset("DRAFT"));
    s.solve();
    const Hierarchy& h = s.hierarchy();
    const int src = cluster_of(h, 2 * 17 * 17);
    ASSERT_GE(src, 0) << "no cluster of the plate's and the wall's faces";
    ASSERT_TRUE(h.has_facing_summary(src));
    const Node& P = h.nodes[size_t(src)];
    const int rcv = probe_leaf(s, probe);
    ASSERT_GE(rcv, 0);
    // From the cluster's centre: half along +x (the wall's normal), most along +y, 2 % up.
    const Vec3 c = P.center * h.unit + h.origin;  // world
    const Vec3 x = h.to_internal(c + normalize(Vec3{0.5, 0.866, 0.02}) * 6.0);
    const Vec3 d = normalize(x - P.center);
    ASSERT_LT(dot(d, Vec3{0, 0, 1}), 0.05);
    const Vec3 n = normalize(P.center - x);
    expect_unbiased(coupling_estimates(s, src, {plate, wall}, x, n, rcv, 2000, 9000), "a two-normal cluster's coupling",
                    2.0);
}

TEST(FinalGather, AnElementSendersTransferIsItsChildrensSummed) {
    // An element sender's point transfer uses the exact point-to-polygon kernel: with nothing
    // between, the couplings of its four quadtree children add up to the element's.
    SceneDesc sc;
    scenes::add_grid(sc, "panel", -1, {Vec3{0, 1, 1}, Vec3{1, 1, 1}, Vec3{1, 0, 1}, Vec3{0, 0, 1}}, 1, 1, Rgb::all(0.5), {},
                     false);  // facing down
    scenes::add_grid(sc, "floor", -1, {Vec3{-1, -1, 0}, Vec3{2, -1, 0}, Vec3{2, 2, 0}, Vec3{-1, 2, 0}}, 1, 1, Rgb::all(0.5),
                     {}, false);
    Hierarchy h;
    h.build(sc, true);
    h.set_pocket_sets();
    auto root_of = [&](int object) {
        const Node& o = h.nodes[size_t(h.object_node[size_t(object)])];
        return o.is_cluster() ? h.surface_geom[size_t(o.surf_begin)].root : h.object_node[size_t(object)];
    };
    const int panel = root_of(0), floor = root_of(1);
    ASSERT_LT(h.nodes[size_t(panel)].normal.z, -0.99);
    h.subdivide(panel);
    Visibility vis;
    vis.commit();
    for (const Vec3& at : {Vec3{0.3, 0.4, 0}, Vec3{-0.6, 1.7, 0}, Vec3{1.0, 0.0, 0}}) {
        const Vec3 x = h.to_internal(at), n{0, 0, 1};
        std::vector<std::pair<int, float>> samples;
        PointRayStream whole(vis);
        const double F = point_transfer(h, whole, panel, x, n, floor, 64, 5, samples).F;
        double sum = 0;
        for (int c : h.nodes[size_t(panel)].children) {
            PointRayStream part(vis);
            sum += point_transfer(h, part, c, x, n, floor, 16, 5, samples).F;
        }
        ASSERT_GT(F, 0.0);
        EXPECT_NEAR(sum, F, 1e-9 * F) << at.x << " " << at.y;
    }
}
