// The live drag's preview (Solver::preview): direct light re-traced at the dragged object's
// new place, the rest as solved, and nothing of the solution changed.
#include <gtest/gtest.h>

#include "test_util.h"

using namespace radiosity;
using namespace radiosity::testing;

namespace {

// The corners of every object with a preview's patches applied.
std::vector<float> patched(const Solver& s, const std::vector<CornerPatch>& patches) {
    std::vector<std::vector<float>> per;
    for (size_t o = 0; o < s.scene().objects().size(); ++o) per.push_back(s.corner_radiance(int(o)));
    for (const CornerPatch& p : patches)
        for (size_t k = 0; k < p.corners.size(); ++k)
            for (int c = 0; c < 3; ++c) per[size_t(p.object)][3 * size_t(p.corners[k]) + size_t(c)] = p.values[3 * k + size_t(c)];
    std::vector<float> out;
    for (const auto& v : per) out.insert(out.end(), v.begin(), v.end());
    return out;
}

// Solves `scene`, previews `object` moved by m, then updates to it: the colours before, the
// preview's and the update's, and the preview's counts.
struct Drag {
    std::vector<float> before, shown, truth;
    FinalGather::PreviewCounts k;
    double stale() const { return nrmse(before, truth); }
    double preview() const { return nrmse(shown, truth); }
};
Drag drag(const SceneDesc& scene, int object, const std::array<double, 16>& m) {
    Solver s(scene, dynamic_settings());
    s.solve();
    Drag d;
    d.before = s.all_corner_radiance();
    d.shown = patched(s, s.preview({{object, m}}, &d.k));
    s.move_object(object, m);
    s.update();
    d.truth = s.all_corner_radiance();
    return d;
}

// Floor corners (object 0) of the box on the floor that lie under the box's bottom at x0.
std::vector<size_t> footprint(const SceneDesc& s, double x0) {
    const ObjectDesc& floor = s.objects()[0];
    std::vector<size_t> out;
    for (size_t c = 0; c < floor.corner_count(); ++c) {
        const Vec3& v = floor.vertices[size_t(floor.corner_verts[c])];
        if (v.x > x0 + 0.05 && v.x < x0 + 0.95 && v.y > -0.15 && v.y < 0.75) out.push_back(c);
    }
    return out;
}

}  // namespace

TEST(Preview, ChangesNothingOfTheSolution) {
    const std::array<double, 16> m = translation({35.6, 60.8, 0});
    Solver a(scenes::box_room(4), dynamic_settings()), b(scenes::box_room(4), dynamic_settings());
    a.solve();
    b.solve();
    const std::vector<float> before = a.all_corner_radiance();
    FinalGather::PreviewCounts k;
    const std::vector<CornerPatch> patches = a.preview({{2, m}}, &k);
    EXPECT_FALSE(patches.empty());
    EXPECT_GT(k.points, 0);
    EXPECT_GT(k.rays, 0);
    EXPECT_EQ(a.all_corner_radiance(), before);
    // The update after a preview is the update without one, bit for bit (Embree's placement
    // restored, no record touched).
    a.move_object(2, m);
    b.move_object(2, m);
    a.update();
    b.update();
    EXPECT_EQ(a.all_corner_radiance(), b.all_corner_radiance());
    // A preview followed by an update that moves something else (a drag cancelled with Esc,
    // then another object moved): the dragged object's geometry is what it was, bit for bit.
    // (A tilted panel: axis-aligned faces keep their normals' bits whichever way they are made.)
    SceneDesc tilted = scenes::box_room(4);
    const int panel = scenes::add_grid(tilted, "panel", tilted.add_cluster("Panel"),
                                       {Vec3{40, 200, 10}, Vec3{100, 230, 20}, Vec3{90, 250, 80}, Vec3{30, 220, 70}}, 3, 3,
                                       Rgb::all(0.6), {});
    Solver c(tilted, dynamic_settings()), e(tilted, dynamic_settings());
    c.solve();
    e.solve();
    const double ca = std::cos(0.4), sa = std::sin(0.4);
    const std::array<double, 16> turn = {ca, -sa, 0, 12, sa, ca, 0, -7, 0, 0, 1, 3, 0, 0, 0, 1};
    c.preview({{panel, turn}});
    EXPECT_TRUE(c.hierarchy().surface_geom_current());  // the samplers' tables put back too
    for (Solver* x : {&c, &e}) {
        x->move_object(3, translation({-20, -30, 0}));
        x->update();
    }
    EXPECT_EQ(c.all_corner_radiance(), e.all_corner_radiance());
    for (size_t i = 0; i < c.hierarchy().nodes.size(); ++i) {
        const Node &u = c.hierarchy().nodes[i], &v = e.hierarchy().nodes[i];
        ASSERT_TRUE(u.normal.x == v.normal.x && u.normal.y == v.normal.y && u.normal.z == v.normal.z &&
                    u.center.x == v.center.x && u.radius == v.radius)
            << "node " << i;
    }
    // No move: no patch.
    EXPECT_TRUE(a.preview({}).empty());
    // A placement the solution already has: nothing to re-trace.
    EXPECT_TRUE(a.preview({{2, m}}).empty());
}

// Between two steps of one drag the dragged object stays where the last step put it (no save
// and put back a step); every other call puts it back first. A drag run so shows what it shows
// with the placement put back between its steps, and leaves the solution as a solver that
// never previewed has it, bit for bit.
TEST(Preview, ADragGoesOnFromWhereItsLastStepLeftTheObject) {
    const SceneDesc scene = scenes::box_room(4);
    Solver a(scene, dynamic_settings()), b(scene, dynamic_settings()), c(scene, dynamic_settings());
    for (Solver* x : {&a, &b, &c}) x->solve();
    auto pose = [](int k) {
        const double ca = std::cos(0.15 * k), sa = std::sin(0.15 * k);
        return std::array<double, 16>{ca, -sa, 0, 9.0 * k, sa, ca, 0, 15.0 * k, 0, 0, 1, 0, 0, 0, 0, 1};
    };
    // Box 2 dragged, then box 3 (another drag), then box 2 again, then both together.
    std::vector<std::map<int, std::array<double, 16>>> steps;
    for (int k = 1; k <= 4; ++k) steps.push_back({{2, pose(k)}});
    steps.push_back({{3, translation({-20, -30, 0})}});
    steps.push_back({{2, pose(5)}});
    steps.push_back({{2, pose(6)}, {3, translation({-25, -30, 0})}});
    steps.push_back({{2, pose(7)}, {3, translation({-30, -30, 0})}});
    for (size_t j = 0; j < steps.size(); ++j) {
        FinalGather::PreviewCounts ka, kb;
        const std::vector<CornerPatch> pa = a.preview(steps[j], &ka);
        (void)b.hierarchy();  // puts b's placement back between its steps
        const std::vector<CornerPatch> pb = b.preview(steps[j], &kb);
        (void)b.hierarchy();
        ASSERT_FALSE(pa.empty()) << "step " << j;
        ASSERT_EQ(pa.size(), pb.size()) << "step " << j;
        for (size_t i = 0; i < pa.size(); ++i) {
            EXPECT_EQ(pa[i].object, pb[i].object);
            EXPECT_EQ(pa[i].corners, pb[i].corners) << "step " << j;
            EXPECT_EQ(pa[i].values, pb[i].values) << "step " << j;
        }
        EXPECT_EQ(ka.points, kb.points);
        EXPECT_EQ(ka.rays, kb.rays);
    }
    // After the drag: the solution as never previewed (hierarchy, Embree's placement, output).
    EXPECT_TRUE(a.hierarchy().surface_geom_current());
    ASSERT_EQ(a.hierarchy().nodes.size(), c.hierarchy().nodes.size());
    for (size_t i = 0; i < c.hierarchy().nodes.size(); ++i) {
        const Node &u = a.hierarchy().nodes[i], &v = c.hierarchy().nodes[i];
        bool same = u.normal.x == v.normal.x && u.normal.y == v.normal.y && u.normal.z == v.normal.z &&
                    u.center.x == v.center.x && u.center.y == v.center.y && u.radius == v.radius && u.area == v.area &&
                    u.poly.n == v.poly.n;
        for (int k = 0; same && k < u.poly.n; ++k)
            same = u.poly.v[size_t(k)].x == v.poly.v[size_t(k)].x && u.poly.v[size_t(k)].y == v.poly.v[size_t(k)].y;
        ASSERT_TRUE(same) << "node " << i;
    }
    EXPECT_EQ(a.hierarchy().area_prefix, c.hierarchy().area_prefix);
    EXPECT_EQ(a.all_corner_radiance(), c.all_corner_radiance());
    // A drag left placed, then an update of another move: the update as without the drag.
    a.preview({{2, pose(8)}});
    for (Solver* x : {&a, &c}) {
        x->move_object(2, pose(3));
        x->update();
    }
    EXPECT_EQ(a.all_corner_radiance(), c.all_corner_radiance());
}

TEST(Preview, RejectsWhatMoveObjectRejects) {
    Solver s(scenes::box_room(4), dynamic_settings());
    EXPECT_THROW(s.preview({}), std::logic_error);  // not solved
    s.solve();
    std::array<double, 16> scaled = translation({1, 0, 0});
    scaled[0] = 2;
    EXPECT_THROW(s.preview({{2, scaled}}), InputError);
    std::array<double, 16> nan = translation({1, 0, 0});
    nan[3] = std::nan("");
    EXPECT_THROW(s.preview({{2, nan}}), InputError);
    EXPECT_THROW(s.preview({{99, translation({1, 0, 0})}}), InputError);
}

// A box dragged under the ceiling panel of the box room: its shadow and the light on its own
// faces follow, so the preview is much closer to the update than the old colours are.
TEST(Preview, FollowsTheEmitterLightOfADraggedBox) {
    const Drag d = drag(scenes::box_room(4), 2, translation({35.6, 60.8, 0}));
    std::printf("[ figure ] box room drag: old colours %.4f, preview %.4f NRMSE from the update; %lld points, %lld "
                "transfers, %lld rays\n",
                d.stale(), d.preview(), (long long)d.k.points, (long long)d.k.transfers, (long long)d.k.rays);
    EXPECT_GT(d.k.transfers, 0);
    EXPECT_LT(d.preview(), 0.7 * d.stale());
}

// A box standing on a floor under a point light, dragged 1.2 m: the floor it stood on is lit
// in the preview (gathered afresh), the floor it stands on now is unlit, the shadow moves.
TEST(Preview, FootprintAndShadowOfABoxOnAFloorFollow) {
    const SceneDesc scene = scenes::point_light_box_on_floor({0.3, 0.2, 2.5});
    const Drag d = drag(scene, 1, translation({-1.2, 0, 0}));
    const std::vector<float>&before = d.before, &shown = d.shown, &truth = d.truth;
    std::printf("[ figure ] box on a floor dragged: old colours %.4f, preview %.4f NRMSE from the update; uncovered "
                "%lld, covered %lld, lamps %lld\n",
                d.stale(), d.preview(), (long long)d.k.uncovered, (long long)d.k.covered, (long long)d.k.lamps);
    EXPECT_GT(d.k.uncovered, 0);
    EXPECT_GT(d.k.covered, 0);
    EXPECT_LT(d.preview(), 0.5 * d.stale());
    const std::vector<size_t> old_place = footprint(scene, 0.1), new_place = footprint(scene, -1.1);
    ASSERT_FALSE(old_place.empty());
    ASSERT_FALSE(new_place.empty());
    for (size_t c : old_place) {
        EXPECT_EQ(before[3 * c], 0.f) << "corner " << c << " was under the box";
        EXPECT_GT(shown[3 * c], 0.5f * truth[3 * c]) << "corner " << c << " is lit again";
    }
    for (size_t c : new_place) {
        EXPECT_GT(before[3 * c], 0.f) << "corner " << c;
        EXPECT_EQ(shown[3 * c], truth[3 * c]) << "corner " << c << " is under the box now";
    }
}

// The box lifted off the floor while dragged: its bottom, covered and unlit in the bake, sees
// the lit floor now; the preview gathers it afresh instead of showing it black until the update.
TEST(Preview, ABoxLiftedOffTheFloorShowsItsBottomLit) {
    const SceneDesc scene = scenes::point_light_box_on_floor({0.3, 0.2, 2.5});
    const Drag d = drag(scene, 1, translation({-1.2, 0, 0.4}));
    const ObjectDesc& box = scene.objects()[1];
    const size_t first = 3 * scene.objects()[0].corner_count();
    double bottom_min = 1e300;
    for (const Vec3& v : box.vertices) bottom_min = std::min(bottom_min, v.z);
    std::printf("[ figure ] box lifted while dragged: old colours %.4f, preview %.4f NRMSE from the update; uncovered %lld\n",
                d.stale(), d.preview(), (long long)d.k.uncovered);
    int bottom = 0;
    for (size_t c = 0; c < box.corner_count(); ++c) {
        const Vec3& v = box.vertices[size_t(box.corner_verts[c])];
        if (v.z > bottom_min + 1e-9) continue;
        const size_t i = first + 3 * c;
        if (d.before[i] > 0.f) continue;  // on the rim: its face beside it is lit
        ++bottom;
        EXPECT_GT(d.truth[i], 0.f) << "bottom corner " << c << " sees the floor now";
        EXPECT_GT(d.shown[i], 0.3f * d.truth[i]) << "bottom corner " << c << " is not shown black";
    }
    EXPECT_GT(bottom, 0);
    EXPECT_GT(d.k.uncovered, 0);
}

// The ceiling panel itself dragged (an emitting mesh: its nodes go with it for the preview):
// the light follows.
TEST(Preview, FollowsADraggedEmitter) {
    const Drag d = drag(scenes::box_room(4), 1, translation({-60, -40, 0}));
    std::printf("[ figure ] ceiling panel dragged: old colours %.4f, preview %.4f NRMSE from the update\n", d.stale(),
                d.preview());
    EXPECT_GT(d.k.transfers, 0);
    EXPECT_LT(d.preview(), 0.5 * d.stale());
}

// A step with little work (Settings::preview_work) relights the points nearest the dragged box
// first, each exactly as a step without a limit would, and leaves the rest showing what an
// earlier step of the drag showed; steps at one place take turns over the box's own points.
TEST(Preview, AStepWithLittleWorkRelightsTheNearestAndKeepsTheRest) {
    const std::array<double, 16> m = translation({-1.2, 0, 0});
    Solver s(scenes::point_light_box_on_floor({0.3, 0.2, 2.5}), dynamic_settings());
    s.solve();
    const std::vector<float> base = s.all_corner_radiance();
    FinalGather::PreviewCounts all, part;
    const std::vector<float> full = patched(s, s.preview({{1, m}}, &all, 0));
    EXPECT_EQ(all.deferred, 0);
    constexpr int64_t kWork = 20000;
    const std::vector<float> first = patched(s, s.preview({{1, m}}, &part, kWork));
    std::printf("[ figure ] box on a floor, a step of %lld work: %lld points relit (%lld without a limit), %lld deferred\n",
                (long long)kWork, (long long)part.points, (long long)all.points, (long long)part.deferred);
    EXPECT_GT(part.deferred, 0);
    EXPECT_LT(part.points, all.points);
    EXPECT_EQ(part.covered, all.covered);  // the floor under the new place first
    size_t relit = 0, kept = 0;
    for (size_t i = 0; i < full.size(); ++i) {
        if (full[i] == base[i]) continue;
        if (first[i] == full[i]) {
            ++relit;
        } else {
            ++kept;
            EXPECT_EQ(first[i], base[i]) << "value " << i << ": neither relit nor the bake's";
        }
    }
    EXPECT_GT(relit, 0u);
    EXPECT_GT(kept, 0u);
    // Steps at the same place: the box's own corners take turns until all are relit.
    const size_t box_begin = 3 * s.scene().objects()[0].corner_count();
    std::vector<float> later;
    for (int k = 0; k < 40; ++k) later = patched(s, s.preview({{1, m}}, nullptr, kWork));
    for (size_t i = box_begin; i < later.size(); ++i) ASSERT_EQ(later[i], full[i]) << "box value " << i << " base " << base[i] << " first " << first[i];
    // After an update the shown changes are forgotten: a step elsewhere shows each value
    // relit or as the new solution has it.
    s.move_object(1, m);
    s.update();
    const std::vector<float> now = s.all_corner_radiance();
    const std::array<double, 16> back = translation({0.4, 0, 0});
    const std::vector<float> whole = patched(s, s.preview({{1, back}}, nullptr, 0));
    const std::vector<float> step = patched(s, s.preview({{1, back}}, &part, kWork));
    EXPECT_GT(part.deferred, 0);
    for (size_t i = 0; i < step.size(); ++i) ASSERT_TRUE(step[i] == whole[i] || step[i] == now[i]) << "value " << i;
}

// A preview places the dragged object without remaking the whole scene's tables (its clusters
// from their children, the tables where its surfaces are): what a whole placement gives, up
// to rounding.
TEST(Preview, ItsPlacementIsTheWholeOnesUpToRounding) {
    const SceneDesc scene = scenes::point_light_box_on_floor({0.3, 0.2, 2.5});
    Hierarchy whole;
    whole.build(scene, true);
    Hierarchy part = whole;
    Rigid q;
    const double c = std::cos(0.6), s = std::sin(0.6);
    q.R = {c, -s, 0, s, c, 0, 0, 0, 1};
    q.t = Vec3{-0.7, 0.3, 0};
    whole.place_object(1, q, true);
    part.place_object(1, q, false);
    auto near = [](double a, double b) { return std::abs(a - b) <= 1e-12 * std::max(1.0, std::abs(b)); };
    ASSERT_EQ(part.nodes.size(), whole.nodes.size());
    for (size_t i = 0; i < whole.nodes.size(); ++i) {
        const Node &a = part.nodes[i], &b = whole.nodes[i];
        ASSERT_TRUE(near(a.area, b.area) && near(a.center.x, b.center.x) && near(a.center.y, b.center.y) &&
                    near(a.center.z, b.center.z) && near(a.radius, b.radius) && near(a.box.lo.x, b.box.lo.x) &&
                    near(a.box.hi.y, b.box.hi.y))
            << "node " << i;
        for (size_t k = 0; k < a.W.size(); ++k) ASSERT_TRUE(near(a.W[k], b.W[k])) << "node " << i << " bin " << k;
    }
    ASSERT_EQ(part.surface_geom.size(), whole.surface_geom.size());
    for (size_t i = 0; i < whole.surface_geom.size(); ++i) {
        EXPECT_EQ(part.surface_geom[i].area, whole.surface_geom[i].area);
        EXPECT_EQ(part.surface_geom[i].poly.v[0].x, whole.surface_geom[i].poly.v[0].x) << "surface " << i;
        EXPECT_EQ(part.surface_geom[i].normal.y, whole.surface_geom[i].normal.y) << "surface " << i;
        ASSERT_TRUE(near(part.area_prefix[i + 1], whole.area_prefix[i + 1]));
    }
    ASSERT_EQ(part.sampler_records.size(), whole.sampler_records.size());
    for (size_t k = 0; k < whole.sampler_records.size(); ++k) {
        ASSERT_TRUE(near(part.sampler_records[k].area, whole.sampler_records[k].area)) << "record " << k;
        for (size_t b = 0; b < whole.sampler_records[k].W.size(); ++b)
            ASSERT_TRUE(near(part.sampler_records[k].W[b], whole.sampler_records[k].W[b])) << "record " << k;
    }
    for (size_t i = 0; i < whole.nodes.size(); ++i)
        EXPECT_EQ(part.has_facing_summary(int(i)), whole.has_facing_summary(int(i))) << "node " << i;
}

// A step that drags the object far outside the scene (ten million of its sizes): the points
// lie in the farthest distance ring from the boxes, and every value shown stays finite.
TEST(Preview, ADragFarOutsideTheSceneStaysFinite) {
    Solver s(scenes::point_light_box_on_floor({0.3, 0.2, 2.5}), dynamic_settings());
    s.solve();
    const std::array<double, 16> m = translation({3e7, -2e7, 1e7});
    for (int64_t work : {int64_t(0), int64_t(20000)}) {
        FinalGather::PreviewCounts k;
        const std::vector<float> shown = patched(s, s.preview({{1, m}}, &k, work));
        for (size_t i = 0; i < shown.size(); ++i) ASSERT_TRUE(std::isfinite(shown[i])) << "value " << i;
        EXPECT_GT(k.points, 0);
    }
}
