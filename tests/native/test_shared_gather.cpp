// Shared gathers (Settings::gather_share): corners near a gathered neighbour take its bounced
// light and gather only their lamps and emitting senders. A finely gridded room shares most of
// its corners at a fraction of the rays, with the same output within the preset's noise, and
// the corners at the foot of a box -- where bounced light changes within centimetres -- keep
// their own gathers.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

#include "test_util.h"

using namespace radiosity;
using namespace radiosity::testing;

namespace {

// A 4 x 4 x 2.5 m room of 24 x 24 quads a face, an emitting panel under its ceiling and a
// 0.6 m box standing on its floor.
SceneDesc gridded_room() {
    SceneDesc s = lamp_room(24);
    scenes::add_box(s, "box", -1, {1.0, 1.0, 0.0}, {1.6, 1.6, 0.6}, 2, Rgb{0.7, 0.4, 0.3}, {});
    return s;
}

struct Bake {
    std::vector<float> room;  // corner radiance, RGB
    Stats stats;
};

Bake bake(const char* preset, double share) {
    Settings st = Settings::preset(preset);
    st.gather_share = share;
    Solver s(gridded_room(), st);
    s.solve();
    return {s.corner_radiance(0), s.stats()};
}

}  // namespace

TEST(SharedGather, GriddedRoomSharesMostCornersAsAccuratelyAsItGathersThem) {
    const Bake own = bake("DRAFT", 0.0);
    const Bake shared = bake("DRAFT", 0.3);
    const Bake ref = bake("HIGH", 0.0);  // the yardstick: every corner gathered, 16x the rays
    ASSERT_EQ(own.room.size(), shared.room.size());
    ASSERT_EQ(own.room.size(), ref.room.size());
    EXPECT_EQ(own.stats.gather_shared, 0);
    const double share = double(shared.stats.gather_shared) / double(shared.stats.gather_points);
    const double rays = double(shared.stats.gather_rays) / double(own.stats.gather_rays);
    // Relative error per corner (green) against the reference, over every lit corner.
    auto rms = [&](const std::vector<float>& x, double* worst, size_t* at) {
        double sum2 = 0;
        size_t n = 0;
        for (size_t k = 1; k < x.size(); k += 3) {
            EXPECT_TRUE(std::isfinite(x[k]));
            const double r = ref.room[k];
            if (!(r > 1e-4)) continue;
            const double d = (double(x[k]) - r) / r;
            sum2 += d * d;
            if (std::fabs(d) > *worst) *worst = std::fabs(d), *at = k / 3;
            ++n;
        }
        return std::sqrt(sum2 / double(std::max<size_t>(n, 1)));
    };
    double worst_own = 0, worst_shared = 0;
    size_t at_own = 0, at_shared = 0;
    const double e_own = rms(own.room, &worst_own, &at_own), e_shared = rms(shared.room, &worst_shared, &at_shared);
    std::printf("[ figure ] %.0f %% of %lld points shared, %.2fx the gather rays; error against HIGH %.2f %% gathered, "
                "%.2f %% shared (worst corner %.1f %% at %zu, %.1f %% at %zu)\n",
                100 * share, (long long)shared.stats.gather_points, rays, 100 * e_own, 100 * e_shared, 100 * worst_own, at_own,
                100 * worst_shared, at_shared);
    EXPECT_GT(share, 0.5);
    EXPECT_LT(rays, 0.6);
    // A shared corner takes its lender's light without Ward's gradients: about the gathered
    // corners' error plus that of the interpolation (0.3-0.6 points here over seeds 1-5).
    EXPECT_LT(e_shared, 1.3 * e_own);
}

TEST(SharedGather, CornersAtTheFootOfABoxKeepTheirOwnGather) {
    // The floor's corners within 12 cm of the box's foot: their bounced light changes within
    // centimetres (the box hides half of what they see), so none may share.
    const Bake own = bake("DRAFT", 0.0);
    const Bake shared = bake("DRAFT", 0.3);
    const SceneDesc scene = gridded_room();
    const ObjectDesc& room = scene.objects()[0];
    const size_t floor_corners = 24 * 24 * 4;  // add_box's first face is the floor (-z)
    double worst = 0;
    int near = 0;
    for (size_t c = 0; c < floor_corners; ++c) {
        const Vec3 v = room.vertices[size_t(room.corner_verts[c])];
        const double dx = std::max({1.0 - v.x, 0.0, v.x - 1.6}), dy = std::max({1.0 - v.y, 0.0, v.y - 1.6});
        if (std::hypot(dx, dy) > 0.12) continue;
        const double a = own.room[3 * c + 1], b = shared.room[3 * c + 1];
        if (!(a > 1e-4)) continue;  // covered by the box: 0 in both
        worst = std::max(worst, std::fabs(b - a) / a);
        ++near;
    }
    std::printf("[ figure ] %d floor corners at the box's foot: worst %.1f %% apart\n", near, 100 * worst);
    EXPECT_GT(near, 8);
    EXPECT_LT(worst, 0.05);
}

TEST(SharedGather, CornersOnAnOpenEdgeGatherTheirOwn) {
    // A box open at its front (y = 0), lit by a panel under its ceiling: the ceiling's light
    // falls toward the opening faster than the distance to what its corners see says. A
    // vertex on an edge of one polygon only neither borrows nor lends: its value is the one
    // its own gather gives (borrowing, the edge's corners were up to 19 % off it).
    SceneDesc s;
    const Rgb rho = Rgb::all(0.7);
    scenes::add_grid(s, "floor", -1, {Vec3{0, 0, 0}, Vec3{1, 0, 0}, Vec3{1, 1, 0}, Vec3{0, 1, 0}}, 12, 12, rho, {});
    scenes::add_grid(s, "ceiling", -1, {Vec3{0, 0, 1}, Vec3{0, 1, 1}, Vec3{1, 1, 1}, Vec3{1, 0, 1}}, 12, 12, rho, {});
    scenes::add_grid(s, "back", -1, {Vec3{0, 1, 0}, Vec3{1, 1, 0}, Vec3{1, 1, 1}, Vec3{0, 1, 1}}, 12, 12, rho, {});
    scenes::add_grid(s, "left", -1, {Vec3{0, 0, 0}, Vec3{0, 1, 0}, Vec3{0, 1, 1}, Vec3{0, 0, 1}}, 12, 12, rho, {});
    scenes::add_grid(s, "right", -1, {Vec3{1, 0, 0}, Vec3{1, 0, 1}, Vec3{1, 1, 1}, Vec3{1, 1, 0}}, 12, 12, rho, {});
    scenes::add_grid(s, "lamp", -1, {Vec3{0.4, 0.4, 0.98}, Vec3{0.4, 0.6, 0.98}, Vec3{0.6, 0.6, 0.98}, Vec3{0.6, 0.4, 0.98}},
                     1, 1, {}, Rgb::all(10.0), false);
    auto ceiling = [&](double share, Stats& st) {
        Settings set = Settings::preset("DRAFT");
        set.gather_share = share;
        Solver solver(s, set);
        solver.solve();
        st = solver.stats();
        return solver.corner_radiance(1);
    };
    Stats st_own, st_shared;
    const std::vector<float> own = ceiling(0.0, st_own), shared = ceiling(0.3, st_shared);
    const ObjectDesc& o = s.objects()[1];
    double worst = 0;
    int on_edge = 0;
    for (size_t c = 0; c < o.corner_count(); ++c) {
        if (o.vertices[size_t(o.corner_verts[c])].y > 1e-9) continue;
        const double a = own[3 * c + 1], b = shared[3 * c + 1];
        ASSERT_GT(a, 0.0);
        worst = std::max(worst, std::fabs(b - a) / a);
        ++on_edge;
    }
    std::printf("[ figure ] %lld of %lld points shared; %d ceiling corners on the open edge: worst %.2g apart from their "
                "own gathers\n", (long long)st_shared.gather_shared, (long long)st_shared.gather_points, on_edge, worst);
    EXPECT_GT(st_shared.gather_shared, st_shared.gather_points / 10);
    EXPECT_EQ(on_edge, 11 * 2 + 2);
    EXPECT_LT(worst, 1e-6);
}

// A point that may borrow probes its own reach with 16 rays; after a move, a retrace keeps the
// probe where none of those rays meets the moved box's old or new box before where it ended.
// Every probe so kept is what casting it again gives (Settings::replay_rays off casts every
// probe), bit for bit, and so is every corner, through a slide and a turn of the box.
TEST(SharedGather, KeptProbesAreWhatCastingThemGives) {
    const double a = 0.4, ca = std::cos(a), sa = std::sin(a);
    // The box (1.0-1.6 m square) slid by (0.9, 0.5), then also turned about its centre.
    const double c = 1.3;
    const std::array<double, 16> turn = {ca, -sa, 0, c - (ca * c - sa * c) + 0.9, sa, ca, 0, c - (sa * c + ca * c) + 0.5,
                                         0,  0,   1, 0,                           0,  0,  0, 1};
    std::vector<double> probes[2][2];
    std::vector<float> corners[2];
    int64_t cast[2] = {0, 0}, kept[2] = {0, 0};
    for (int replay = 0; replay < 2; ++replay) {
        Settings st = Settings::preset("DRAFT");  // gather_share 0.3: most points may borrow
        st.replay_rays = replay == 1;
        Solver s(gridded_room(), st);
        s.solve();
        const int box = int(s.scene().objects().size()) - 1;
        int step = 0;
        for (const std::array<double, 16>& m : {translation({0.9, 0.5, 0}), turn}) {
            s.move_object(box, m);
            s.update();
            ASSERT_TRUE(s.stats().mode_incremental);
            probes[replay][step++] = s.output_probes();
            cast[replay] += s.stats().gather_probe_rays;
            kept[replay] += s.stats().gather_probes_kept;
        }
        corners[replay] = s.all_corner_radiance();
    }
    std::printf("[ figure ] 2 updates: %lld probes kept, %lld probe rays cast replaying; %lld casting every ray\n",
                (long long)kept[1], (long long)cast[1], (long long)cast[0]);
    for (int step = 0; step < 2; ++step) {
        ASSERT_EQ(probes[1][step].size(), probes[0][step].size());
        size_t made = 0;
        for (size_t i = 0; i < probes[0][step].size(); ++i) {
            ASSERT_EQ(probes[1][step][i], probes[0][step][i]) << "update " << step << ", point " << i;
            made += probes[0][step][i] >= 0;
        }
        EXPECT_GT(made, 100u);
    }
    ASSERT_EQ(corners[1].size(), corners[0].size());
    for (size_t i = 0; i < corners[0].size(); ++i) ASSERT_EQ(corners[1][i], corners[0][i]) << "corner value " << i;
    EXPECT_EQ(kept[0], 0);
    EXPECT_GT(kept[1], 0);
    EXPECT_GT(cast[1], 0);  // the probes near the box's old and new places are cast again
    EXPECT_LT(cast[1], cast[0]);
}
