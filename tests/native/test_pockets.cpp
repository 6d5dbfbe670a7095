// Closed pockets (pockets.cpp): which surfaces can exchange light at all. A closed crate's
// inside and what lies in it form a pocket of their own; a closed room is one pocket with
// everything in it (never cut off from its contents); a crate with an open top is no pocket.
#include <gtest/gtest.h>

#include <array>
#include <set>
#include <string>

#include "test_util.h"

using namespace radiosity;
using namespace radiosity::testing;

namespace {

// Pockets of an object's front (or back) sides.
std::set<int> pockets_of(const Solver& s, int object, bool back) {
    const Hierarchy& h = s.hierarchy();
    std::set<int> out;
    for (const Primitive& p : h.prims) {
        if (p.object != object) continue;
        const int side = back ? p.back : p.front;
        if (side >= 0) out.insert(h.nodes[size_t(h.surfaces[size_t(side)].root)].pocket);
    }
    return out;
}

// The lit room of test_extremes.cpp (two-sided walls, facing in) with a cube at `cube_lo`
// and, when `crate`, a closed crate (a lid: the object "lid" is its top, so the crate can be
// left open) around (0.3..1.3, 0.3..1.3, 0.05..1.05).
SceneDesc room_with_crate(bool lid, Vec3 cube_lo) {
    SceneDesc s;
    scenes::add_box(s, "room", -1, {0, 0, 0}, {3, 3, 2.5}, 3, Rgb::all(0.7), {}, true);
    scenes::add_grid(s, "light", -1, {Vec3{1.25, 1.25, 2.4}, Vec3{1.25, 1.75, 2.4}, Vec3{1.75, 1.75, 2.4}, Vec3{1.75, 1.25, 2.4}},
                     1, 1, {}, Rgb::all(10.0));
    const int c = s.add_cluster("Crate");
    const double a = 0.3, b = 1.3, z0 = 0.05, z1 = 1.05;
    // Five sides, outward (counter-clockwise seen from outside), then the lid.
    scenes::add_grid(s, "bottom", c, {Vec3{a, a, z0}, Vec3{a, b, z0}, Vec3{b, b, z0}, Vec3{b, a, z0}}, 2, 2, Rgb::all(0.6), {});
    scenes::add_grid(s, "south", c, {Vec3{a, a, z0}, Vec3{b, a, z0}, Vec3{b, a, z1}, Vec3{a, a, z1}}, 2, 2, Rgb::all(0.6), {});
    scenes::add_grid(s, "north", c, {Vec3{a, b, z0}, Vec3{a, b, z1}, Vec3{b, b, z1}, Vec3{b, b, z0}}, 2, 2, Rgb::all(0.6), {});
    scenes::add_grid(s, "west", c, {Vec3{a, a, z0}, Vec3{a, a, z1}, Vec3{a, b, z1}, Vec3{a, b, z0}}, 2, 2, Rgb::all(0.6), {});
    scenes::add_grid(s, "east", c, {Vec3{b, a, z0}, Vec3{b, b, z0}, Vec3{b, b, z1}, Vec3{b, a, z1}}, 2, 2, Rgb::all(0.6), {});
    if (lid) scenes::add_grid(s, "lid", c, {Vec3{a, a, z1}, Vec3{b, a, z1}, Vec3{b, b, z1}, Vec3{a, b, z1}}, 2, 2, Rgb::all(0.6), {});
    scenes::add_box(s, "cube", s.add_cluster("Cube"), cube_lo, cube_lo + Vec3{0.2, 0.2, 0.2}, 2, Rgb::all(0.6), {});
    return s;
}

}  // namespace

TEST(Pockets, AClosedCrateAndWhatLiesInItAreAPocketOfTheirOwn) {
    Solver s(room_with_crate(true, {0.7, 0.7, 0.3}), Settings::preset("DRAFT"));
    s.solve();
    const int cube = int(s.scene().objects().size()) - 1;
    const std::set<int> room_in = pockets_of(s, 0, false), room_out = pockets_of(s, 0, true);
    ASSERT_EQ(room_in.size(), 1u);
    const int room = *room_in.begin();
    EXPECT_EQ(room_out, std::set<int>{0}) << "the room's outside sees open space";
    EXPECT_EQ(pockets_of(s, 1, false), room_in) << "the light";
    ASSERT_EQ(pockets_of(s, cube, false).size(), 1u);
    const int crate = *pockets_of(s, cube, false).begin();
    EXPECT_NE(crate, room);
    EXPECT_NE(crate, 0);
    for (int o = 2; o < cube; ++o) {
        // The crate's sides face out (front) into the room, in (back) into the crate.
        EXPECT_EQ(pockets_of(s, o, false), room_in) << s.scene().objects()[size_t(o)].name;
        EXPECT_EQ(pockets_of(s, o, true), std::set<int>{crate}) << s.scene().objects()[size_t(o)].name;
    }
    // The cube's own inside is a pocket too.
    ASSERT_EQ(pockets_of(s, cube, true).size(), 1u);
    EXPECT_NE(*pockets_of(s, cube, true).begin(), crate);
    EXPECT_NE(*pockets_of(s, cube, true).begin(), room);
    // And light keeps out: the cube's radiance is exactly 0.
    for (float v : s.corner_radiance(cube)) ASSERT_EQ(v, 0.f);
}

TEST(Pockets, AnOpenCrateIsNoPocket) {
    // Without its lid the crate's inside sees the room: one space, and the cube in it is lit.
    Solver s(room_with_crate(false, {0.7, 0.7, 0.3}), Settings::preset("DRAFT"));
    s.solve();
    const int cube = int(s.scene().objects().size()) - 1;
    const std::set<int> room_in = pockets_of(s, 0, false);
    EXPECT_EQ(pockets_of(s, cube, false), room_in);
    for (int o = 2; o < cube; ++o) EXPECT_EQ(pockets_of(s, o, true), room_in) << s.scene().objects()[size_t(o)].name;
    double peak = 0;
    for (float v : s.corner_radiance(cube)) peak = std::max(peak, double(v));
    EXPECT_GT(peak, 0.01 * s.reference_radiance());
}

TEST(Pockets, AClosedRoomIsOnePocketWithEverythingInIt) {
    // The furnace room: walls facing in, one-sided, closed; a box in it. Nothing escapes, yet
    // the room is never cut off from the box in it.
    SceneDesc sc;
    scenes::add_box(sc, "room", -1, {0, 0, 0}, {3, 3, 2.5}, 3, Rgb::all(0.5), Rgb::all(1.0), true, false);
    scenes::add_box(sc, "box", sc.add_cluster("Furniture"), {1, 1, 0.1}, {2, 1.5, 1}, 3, Rgb::all(0.5), Rgb::all(1.0));
    Solver s(sc, Settings::preset("DRAFT"));
    s.solve();
    const std::set<int> room = pockets_of(s, 0, false);
    ASSERT_EQ(room.size(), 1u);
    EXPECT_EQ(pockets_of(s, 1, false), room);
    EXPECT_NE(*pockets_of(s, 1, true).begin(), *room.begin()) << "the box's inside";
}

TEST(Pockets, MovingIntoAndOutOfAClosedCrateSolvesInFull) {
    // A move that changes which pocket a surface is in changes which links may exist: the
    // update solves in full, says so, and matches a full solve of the scene it leaves.
    const Vec3 out{2.0, 2.0, 0.3}, in{0.7, 0.7, 0.3};
    Solver s(room_with_crate(true, out), Settings::preset("DRAFT"));
    s.solve();
    const int cube = int(s.scene().objects().size()) - 1;
    auto said = [&] { return has_warning(s, "closed pocket"); };
    s.move_object(cube, translation(in - out));
    s.update();
    EXPECT_TRUE(said());
    EXPECT_FALSE(s.stats().mode_incremental);
    EXPECT_EQ(s.stats().update_fallback, UpdateFallback::pocket_moved);
    for (float v : s.corner_radiance(cube)) ASSERT_EQ(v, 0.f);
    s.move_object(cube, translation(Vec3{2.0, 1.5, 0.3} - out));
    s.update();
    EXPECT_TRUE(said()) << "out of the crate again";
    EXPECT_FALSE(s.stats().mode_incremental);
    double peak = 0;
    for (float v : s.corner_radiance(cube)) peak = std::max(peak, double(v));
    EXPECT_GT(peak, 0.01 * s.reference_radiance()) << "lit again";
    // Within the room a move keeps every pocket: incremental.
    s.move_object(cube, translation(Vec3{2.1, 1.6, 0.3} - out));
    s.update();
    EXPECT_TRUE(s.stats().mode_incremental);
    EXPECT_FALSE(said()) << "the previous update's fallback warning is not this one's";
    EXPECT_EQ(s.stats().update_fallback, UpdateFallback::none);
}

TEST(Pockets, AMoveAwayFromAClosedPocketKeepsItsConfirmationWithoutARay) {
    // A closed pocket's confirmation rays all hit its own surfaces: after a move whose boxes
    // miss the pocket, its confirmation stands as it was. The pockets an update finds are
    // those a full solve of the moved scene finds, and the update casts fewer pocket rays
    // than one that casts every ray again.
    auto scene = [](Vec3 stool_lo) {
        SceneDesc sc = room_with_crate(true, {0.7, 0.7, 0.3});
        scenes::add_box(sc, "stool", sc.add_cluster("Stool"), stool_lo, stool_lo + Vec3{0.4, 0.4, 0.4}, 2, Rgb::all(0.6), {});
        return sc;
    };
    const Vec3 was{2.0, 2.0, 0.0}, by{0.25, -0.3, 0};
    const SceneDesc sc = scene(was);
    const int stool = int(sc.objects().size()) - 1;
    const std::array<double, 16> step = translation(by);
    auto pockets = [](const Solver& s) {
        std::vector<int> p;
        const Hierarchy& h = s.hierarchy();
        for (size_t k = 0; k < h.surfaces.size(); ++k) p.push_back(h.nodes[size_t(h.surfaces[k].root)].pocket);
        return p;
    };
    int64_t pocket_rays[2] = {0, 0};
    std::vector<int> found[2];
    for (int replay = 0; replay < 2; ++replay) {
        Settings st = Settings::preset("DRAFT");
        st.replay_rays = replay == 1;
        Solver s(sc, st);
        s.solve();
        s.move_object(stool, step);
        s.update();
        ASSERT_TRUE(s.stats().mode_incremental);
        for (const auto& [phase, rays] : s.stats().phase_rays)
            if (phase == "pockets") pocket_rays[replay] = rays;
        found[replay] = pockets(s);
    }
    Solver full(scene(was + by), Settings::preset("DRAFT"));
    full.solve();
    const std::vector<int> want = pockets(full);
    std::set<int> closed(want.begin(), want.end());
    EXPECT_GE(closed.size(), 4u) << "open space, the room, the crate, the cubes' insides";
    EXPECT_EQ(found[1], want);
    EXPECT_EQ(found[0], want);
    std::printf("[ figure ] pocket rays of the update: %lld keeping confirmations, %lld casting every ray\n",
                (long long)pocket_rays[1], (long long)pocket_rays[0]);
    EXPECT_LT(2 * pocket_rays[1], pocket_rays[0]);
}
