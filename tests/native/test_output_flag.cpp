// Objects whose colours are not read (ObjectDesc::output false: an instance, an area light, a
// mesh the add-on cannot write): the final gather traces no point at their corners, they read
// their leaves, and they light and shadow the rest as before. What the other objects' points
// find does not depend on which points are traced besides them (each point's rays are seeded
// by its own corner), so their corners are the same bit for bit.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "test_util.h"

using namespace radiosity;
using namespace radiosity::testing;

namespace {

constexpr int kCopy = 3;  // the copy's object id

// The paper's box room (coarse) with Box1 and a copy of it (same size, bluish) in collections
// of their own; the copy's output as given, or no copy at all (its collection kept, empty).
SceneDesc room(bool copy, bool copy_output = true) {
    SceneDesc s;
    scenes::add_box(s, "room", -1, {0, 0, 0}, {300, 300, 250}, 4, Rgb::all(0.7), {}, true);
    scenes::add_grid(s, "light", -1, {Vec3{120, 120, 249}, Vec3{120, 180, 249}, Vec3{180, 180, 249}, Vec3{180, 120, 249}},
                     1, 1, {}, Rgb::all(12.0), false);
    scenes::add_box(s, "Box1", s.add_cluster("Box1"), {84.4, 99.2, 0}, {144.4, 159.2, 100}, 2, Rgb{0.7, 0.3, 0.2}, {});
    const int c = s.add_cluster("Copy");
    if (copy) {
        const int id = scenes::add_box(s, "Copy", c, {190, 180, 0}, {250, 240, 100}, 2, Rgb{0.1, 0.3, 0.8}, {});
        s.objects_mut()[size_t(id)].output = copy_output;
    }
    return s;
}

Settings settings(int gather_rays = 128) {
    Settings st = Settings::preset("DRAFT");
    st.gather_rays = gather_rays;
    return st;
}

bool all_finite(const std::vector<float>& v) {
    for (float x : v)
        if (!std::isfinite(x) || x < 0) return false;
    return true;
}

double sum(const std::vector<float>& v) {
    double s = 0;
    for (float x : v) s += x;
    return s;
}

// Mean radiance (per channel) of the room's corners on the floor (z = 0) around the copy's
// footprint, [190, 250] x [180, 240]: outside it, within `r` of its centre.
Rgb floor_near_copy(const Solver& s, double r) {
    const ObjectDesc& o = s.scene().objects()[0];
    const std::vector<float> c = s.corner_radiance(0);
    Rgb acc;
    int n = 0;
    for (size_t i = 0; i < o.corner_count(); ++i) {
        const Vec3& v = o.vertices[size_t(o.corner_verts[i])];
        const bool under = v.x >= 190 && v.x <= 250 && v.y >= 180 && v.y <= 240;
        if (v.z != 0 || under || std::hypot(v.x - 220, v.y - 210) > r) continue;
        acc += Rgb{c[3 * i], c[3 * i + 1], c[3 * i + 2]};
        ++n;
    }
    return n ? acc / double(n) : acc;
}

// Every object's corners but the copy's, in object order.
std::vector<float> others(const Solver& s) {
    std::vector<float> out;
    for (int o = 0; o < int(s.scene().objects().size()); ++o) {
        if (o == kCopy) continue;
        const std::vector<float> c = s.corner_radiance(o);
        out.insert(out.end(), c.begin(), c.end());
    }
    return out;
}

}  // namespace

TEST(OutputFlag, NoPointsForTheCopyAndTheRestUnchanged) {
    Solver on(room(true, true), settings()), off(room(true, false), settings()), none(room(false), settings());
    on.solve();
    off.solve();
    none.solve();
    const size_t corners = off.scene().objects()[kCopy].corner_count();
    ASSERT_GT(corners, 0u);
    // Only the written objects' corners are gathered, and the copy's points are gone.
    EXPECT_EQ(off.stats().gather_corners, on.stats().gather_corners - int64_t(corners));
    EXPECT_EQ(off.stats().gather_corners, none.stats().gather_corners);
    EXPECT_LT(off.stats().gather_points, on.stats().gather_points);
    EXPECT_GE(off.stats().gather_points, on.stats().gather_points - int64_t(corners));
    EXPECT_LT(off.stats().gather_rays, on.stats().gather_rays);
    EXPECT_GT(on.object_costs()[kCopy].point_rays, 0);
    EXPECT_EQ(off.object_costs()[kCopy].point_rays, 0);
    std::printf("[ figure ] gathered corners %lld of %lld (points %lld of %lld, gather rays %lld of %lld)\n",
                (long long)off.stats().gather_corners, (long long)on.stats().gather_corners,
                (long long)off.stats().gather_points, (long long)on.stats().gather_points,
                (long long)off.stats().gather_rays, (long long)on.stats().gather_rays);

    // The copy's corners read its leaves: finite, lit, and what a solve without a final
    // gather gives (the solution itself does not depend on the flag or the gather).
    const std::vector<float> copy = off.corner_radiance(kCopy);
    ASSERT_EQ(copy.size(), 3 * corners);
    EXPECT_TRUE(all_finite(copy));
    EXPECT_GT(sum(copy), 0);
    Solver leaves(room(true, true), settings(0));
    leaves.solve();
    EXPECT_EQ(copy, leaves.corner_radiance(kCopy));
    // Lighting only: the same fallback.
    const std::vector<float> e = off.corner_irradiance(kCopy);
    ASSERT_EQ(e.size(), 3 * corners);
    EXPECT_TRUE(all_finite(e));

    // Every other corner is the same, bit for bit: no point's trace depends on the others.
    EXPECT_EQ(others(off), others(on));

    // ... and still shadowed by the copy and tinted by its light: the floor around it is
    // darker than without it, and bluer.
    const Rgb with = floor_near_copy(off, 100), without = floor_near_copy(none, 100);
    std::printf("[ figure ] floor around the copy: with it (%.3f %.3f %.3f), without (%.3f %.3f %.3f)\n", with.r,
                with.g, with.b, without.r, without.g, without.b);
    EXPECT_LT(with.r, 0.9 * without.r);
    EXPECT_GT(with.b / with.r, 1.01 * without.b / without.r);
}

TEST(OutputFlag, UpdatesAndThePreviewHonourIt) {
    Solver on(room(true, true), settings()), off(room(true, false), settings());
    on.solve();
    off.solve();
    const size_t corners = off.scene().objects()[kCopy].corner_count();
    // Dragging the copy: the floor's patches (its shadow) are those of the copy with output,
    // and the copy itself gets none.
    const std::array<double, 16> drag = translation({-30, 20, 0});
    FinalGather::PreviewCounts k_on, k_off;
    const std::vector<CornerPatch> p_on = on.preview({{kCopy, drag}}, &k_on);
    const std::vector<CornerPatch> p_off = off.preview({{kCopy, drag}}, &k_off);
    ASSERT_FALSE(p_off.empty());
    auto without_copy = [](const std::vector<CornerPatch>& ps) {
        std::vector<CornerPatch> out;
        for (const CornerPatch& p : ps)
            if (p.object != kCopy) out.push_back(p);
        return out;
    };
    for (const CornerPatch& p : p_off) EXPECT_NE(p.object, kCopy);
    const std::vector<CornerPatch> q_on = without_copy(p_on);
    ASSERT_EQ(q_on.size(), p_off.size());
    for (size_t i = 0; i < p_off.size(); ++i) {
        EXPECT_EQ(q_on[i].object, p_off[i].object);
        EXPECT_EQ(q_on[i].corners, p_off[i].corners);
        EXPECT_EQ(q_on[i].values, p_off[i].values);
    }
    EXPECT_LT(k_off.points, k_on.points);
    // Dragging Box1: nothing of the copy is patched.
    for (const CornerPatch& p : off.preview({{2, translation({20, 10, 0})}})) EXPECT_NE(p.object, kCopy);

    // Moves, then an update (a retrace): the flag holds, the rest matches bit for bit.
    for (Solver* s : {&on, &off}) {
        s->move_object(kCopy, drag);
        s->move_object(2, translation({10, -15, 0}));
        s->update();
        EXPECT_TRUE(s->stats().mode_incremental);
    }
    EXPECT_EQ(off.stats().gather_corners, on.stats().gather_corners - int64_t(corners));
    EXPECT_EQ(off.object_costs()[kCopy].point_rays, 0);
    EXPECT_TRUE(all_finite(off.corner_radiance(kCopy)));
    EXPECT_GT(sum(off.corner_radiance(kCopy)), 0);
    EXPECT_EQ(others(off), others(on));
    // A change of radiance alone (no ray): the same.
    for (Solver* s : {&on, &off}) {
        s->set_emission(1, {Rgb::all(6.0)});
        s->update();
    }
    EXPECT_EQ(off.stats().gather_corners, on.stats().gather_corners - int64_t(corners));
    EXPECT_EQ(others(off), others(on));
    EXPECT_TRUE(all_finite(off.corner_radiance(kCopy)));
}

TEST(OutputFlag, AddedObjectsHonourIt) {
    // The copy added after the solve, through the solver, with output or without.
    Solver on(room(false), settings()), off(room(false), settings());
    on.solve();
    off.solve();
    const int64_t before = off.stats().gather_corners;
    const SceneDesc full = room(true, false);
    ObjectDesc copy = full.objects()[kCopy];
    ASSERT_FALSE(copy.output);
    EXPECT_EQ(off.add_object(copy), kCopy);
    copy.output = true;
    EXPECT_EQ(on.add_object(copy), kCopy);
    on.update();
    off.update();
    EXPECT_EQ(off.stats().objects_added, 1);
    EXPECT_EQ(off.stats().gather_corners, before);
    EXPECT_EQ(on.stats().gather_corners, before + int64_t(copy.corner_count()));
    const std::vector<float> c = off.corner_radiance(kCopy);
    ASSERT_EQ(c.size(), 3 * copy.corner_count());
    EXPECT_TRUE(all_finite(c));
    EXPECT_GT(sum(c), 0);
    EXPECT_EQ(others(off), others(on));
    // Removed again: the slot stays, empty.
    off.remove_object(kCopy);
    off.update();
    EXPECT_EQ(off.stats().gather_corners, before);
    EXPECT_TRUE(off.corner_radiance(kCopy).empty());
}

TEST(OutputFlag, TexturedAndAllSilentObjects) {
    // A textured copy without output: its corners reflect with their own reflectance what the
    // leaves hold (no gather), finite.
    SceneDesc s = room(true, false);
    ObjectDesc& copy = s.objects_mut()[kCopy];
    copy.corner_reflectance.assign(copy.corner_count(), Rgb{0.9, 0.1, 0.1});
    Solver t(s, settings());
    t.solve();
    const std::vector<float> c = t.corner_radiance(kCopy);
    ASSERT_EQ(c.size(), 3 * copy.corner_count());
    EXPECT_TRUE(all_finite(c));
    EXPECT_GT(sum(c), 0);

    // No object with output: nothing gathered, every corner its leaves', and a preview has
    // nothing to show.
    SceneDesc q = room(true, false);
    for (ObjectDesc& o : q.objects_mut()) o.output = false;
    Solver silent(q, settings()), leaves(room(true, true), settings(0));
    silent.solve();
    leaves.solve();
    EXPECT_EQ(silent.stats().gather_points, 0);
    EXPECT_EQ(silent.stats().gather_corners, 0);
    for (int o = 0; o < int(q.objects().size()); ++o) {
        EXPECT_TRUE(all_finite(silent.corner_radiance(o))) << o;
        EXPECT_EQ(silent.corner_radiance(o), leaves.corner_radiance(o)) << o;
    }
    EXPECT_TRUE(silent.preview({{kCopy, translation({-30, 20, 0})}}).empty());
}

// A modifier's evaluated mesh has many corners for each one written (ObjectDesc::
// written_corners): only the read ones get gather points. Read here: the copy's corners at
// even vertices (each such vertex's first corner is read, so its point is where the full
// trace puts it); without shared gathers every read corner is then what the full trace
// gives, bit for bit, and the others read the leaves.
TEST(OutputFlag, OnlyTheCornersReadAreGathered) {
    auto masked = [](bool mask) {
        SceneDesc s = room(true, true);
        ObjectDesc& o = s.objects_mut()[size_t(kCopy)];
        if (mask) {
            o.written_corners.assign(o.corner_count(), 0);
            for (size_t c = 0; c < o.corner_count(); ++c) o.written_corners[c] = o.corner_verts[c] % 2 == 0;
        }
        return s;
    };
    Settings st = settings();
    st.gather_share = 0;
    Solver full(masked(false), st), part(masked(true), st);
    full.solve();
    part.solve();
    const ObjectDesc& o = part.scene().objects()[size_t(kCopy)];
    int64_t read = 0;
    for (size_t c = 0; c < o.corner_count(); ++c) read += o.written(c);
    ASSERT_GT(read, 0);
    ASSERT_LT(read, int64_t(o.corner_count()));
    EXPECT_EQ(part.stats().gather_corners, full.stats().gather_corners - int64_t(o.corner_count()) + read);
    EXPECT_LT(part.stats().gather_points, full.stats().gather_points);
    EXPECT_LT(part.object_costs()[kCopy].point_rays, full.object_costs()[kCopy].point_rays);
    // The memory forecast of the trace counts the points made, not the corners left out.
    EXPECT_LT(part.stats().gather_forecast_bytes, full.stats().gather_forecast_bytes);
    EXPECT_EQ(others(part), others(full));

    Settings no_gather = st;
    no_gather.gather_rays = 0;
    Solver leaves(masked(false), no_gather);
    leaves.solve();
    const std::vector<float> a = full.corner_radiance(kCopy), b = part.corner_radiance(kCopy),
                             l = leaves.corner_radiance(kCopy), e = part.corner_irradiance(kCopy);
    ASSERT_EQ(b.size(), 3 * o.corner_count());
    EXPECT_TRUE(all_finite(b));
    EXPECT_TRUE(all_finite(e));
    for (size_t c = 0; c < o.corner_count(); ++c)
        for (size_t k = 0; k < 3; ++k)
            EXPECT_EQ(b[3 * c + k], o.written(c) ? a[3 * c + k] : l[3 * c + k]) << "corner " << c;

    // A mask of the wrong length is refused.
    SceneDesc bad = room(false);
    ObjectDesc copy = room(true).objects()[size_t(kCopy)];
    copy.written_corners.assign(copy.corner_count() + 1, 1);
    EXPECT_THROW(bad.add_object(copy), InputError);
}
