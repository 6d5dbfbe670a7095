// Objects added to and removed from a solved scene (the goal: "added -> linked in; deleted ->
// removed, not by silently re-solving everything"): the incremental result against a fresh
// full solve of the same scene, the work it takes, and bad input.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "test_util.h"

using namespace radiosity;
using namespace radiosity::testing;

namespace {

// The paper's box room (coarse, as in test_dynamic.cpp), each box optional. Box1 and Box2 sit
// in collections of their own; `keep_empty_clusters` keeps a box's collection when the box is
// left out (as a Blender collection whose object was deleted).
SceneDesc room(bool box1, bool box2, bool keep_empty_clusters = false) {
    SceneDesc s;
    scenes::add_box(s, "room", -1, {0, 0, 0}, {300, 300, 250}, 4, Rgb::all(0.7), {}, true);
    scenes::add_grid(s, "light", -1, {Vec3{120, 120, 249}, Vec3{120, 180, 249}, Vec3{180, 180, 249}, Vec3{180, 120, 249}}, 1, 1,
                     {}, Rgb::all(12.0), false);
    if (box1 || keep_empty_clusters) {
        int c1 = s.add_cluster("Box1");
        if (box1) scenes::add_box(s, "Box1", c1, {84.4, 99.2, 0}, {144.4, 159.2, 100}, 2, Rgb{0.7, 0.3, 0.2}, {});
    }
    if (box2 || keep_empty_clusters) {
        int c2 = s.add_cluster("Box2");
        if (box2) scenes::add_box(s, "Box2", c2, {200, 200, 0}, {260, 250, 60}, 2, Rgb{0.2, 0.4, 0.7}, {});
    }
    return s;
}

// Box2 as a lone object description, in cluster `cluster`.
ObjectDesc box2(int cluster) {
    SceneDesc t;
    for (int c = 0; c <= cluster; ++c) t.add_cluster("c" + std::to_string(c));
    scenes::add_box(t, "Box2", cluster, {200, 200, 0}, {260, 250, 60}, 2, Rgb{0.2, 0.4, 0.7}, {});
    return t.objects()[0];
}

// Corner radiance of the named objects, in that order (ids differ between an updated solver,
// whose removed objects keep their slot, and a fresh one).
std::vector<float> corners_by_name(const Solver& s, const std::vector<std::string>& names) {
    std::vector<float> out;
    for (const std::string& n : names)
        for (size_t o = 0; o < s.scene().objects().size(); ++o)
            if (!s.removed(int(o)) && s.scene().objects()[o].name == n) {
                const std::vector<float> c = s.corner_radiance(int(o));
                out.insert(out.end(), c.begin(), c.end());
            }
    return out;
}

// Work of the last update next to that of a full solve: link evaluations and rays.
struct Work {
    int64_t evaluated = 0, rays = 0;
};
Work work_since(const Solver& s, const Work& before) {
    return {s.stats().links_evaluated - before.evaluated, s.stats().rays - before.rays};
}
Work work_now(const Solver& s) { return {s.stats().links_evaluated, s.stats().rays}; }

void print_work(const char* what, const Solver& inc, const Work& w, const Solver& full, double e) {
    const Stats& s = inc.stats();
    std::printf("[ figure ] %s: incremental vs full NRMSE %.4f; links evaluated %lld (full solve %lld, %.0f %%), "
                "rays %lld (full %lld, %.0f %%), links created %lld, removed %lld, env-env tested %lld "
                "rejected %lld re-evaluated %lld; links %lld vs full %lld, elements %lld vs full %lld; wall time "
                "update / full solve %.0f %% (one run)\n",
                what, e, (long long)w.evaluated, (long long)full.stats().links_evaluated,
                100.0 * double(w.evaluated) / double(full.stats().links_evaluated), (long long)w.rays,
                (long long)full.stats().rays, 100.0 * double(w.rays) / double(full.stats().rays),
                (long long)s.links_created, (long long)s.links_removed, (long long)s.env_env_links_tested,
                (long long)s.env_env_links_rejected, (long long)s.env_env_links_recomputed, (long long)s.links,
                (long long)full.stats().links, (long long)s.elements, (long long)full.stats().elements,
                100.0 * s.seconds_total / full.stats().seconds_total);
}

const std::vector<std::string> kAll = {"room", "light", "Box1", "Box2"};

}  // namespace

// Goal: incremental equals a full solve within 0.5 % NRMSE. Bounded here at 2 %,
// as the move tests are (test_dynamic.cpp); the measured figure is printed.
constexpr double kTol = 0.02;

TEST(Topology, AddedObjectIsLinkedInAndEqualsFullSolve) {
    // Box2's collection exists but is empty at the first solve (a collection whose only object
    // was hidden): the addition makes its cluster node.
    Solver inc(room(true, false, true), dynamic_settings());
    inc.solve();
    const Work w0 = work_now(inc);
    const int id = inc.add_object(box2(1));
    EXPECT_EQ(id, 3);  // the next id
    inc.update();
    EXPECT_TRUE(inc.stats().mode_incremental);
    EXPECT_EQ(inc.stats().objects_added, 1);
    EXPECT_EQ(inc.stats().objects, 4);
    EXPECT_GT(inc.stats().links_created, 0);
    EXPECT_GT(inc.stats().env_env_links_rejected, 0);
    Solver full(room(true, true), dynamic_settings());
    full.solve();
    const double e = nrmse(corners_by_name(inc, kAll), corners_by_name(full, kAll));
    print_work("add Box2", inc, work_since(inc, w0), full, e);
    EXPECT_LE(e, kTol);
    // The box is lit and casts light: its own corners are not black.
    double sum = 0;
    for (float v : inc.corner_radiance(id)) sum += v;
    EXPECT_GT(sum, 0);
    // Less work than a full solve: the environment's links mostly stay.
    EXPECT_LT(work_since(inc, w0).evaluated, full.stats().links_evaluated);
}

TEST(Topology, AddedObjectInANewCollection) {
    // The collection is made through the solver after the solve (Blender: a new collection).
    Solver inc(room(true, false), dynamic_settings());
    inc.solve();
    const int c = inc.add_cluster("Box2");
    EXPECT_EQ(c, 1);
    inc.add_object(box2(c));
    inc.update();
    EXPECT_EQ(inc.stats().objects_added, 1);
    Solver full(room(true, true), dynamic_settings());
    full.solve();
    const double e = nrmse(corners_by_name(inc, kAll), corners_by_name(full, kAll));
    std::printf("[ figure ] add Box2 in a new collection: NRMSE %.4f\n", e);
    EXPECT_LE(e, kTol);
    EXPECT_EQ(inc.stats().clusters, full.stats().clusters);
}

TEST(Topology, RemovedObjectGoesAndEqualsFullSolve) {
    Solver inc(room(true, true), dynamic_settings());
    inc.solve();
    const int64_t links_before = inc.stats().links;
    const Work w0 = work_now(inc);
    inc.remove_object(2);  // Box1
    inc.update();
    EXPECT_TRUE(inc.stats().mode_incremental);
    EXPECT_EQ(inc.stats().objects_removed, 1);
    EXPECT_EQ(inc.stats().objects, 3);
    EXPECT_GT(inc.stats().links_removed, 0);
    EXPECT_TRUE(inc.corner_radiance(2).empty()) << "a removed object's slot is empty";
    // The fresh scene has no Box1 and no collection for it: ids and cluster indices differ,
    // keys (by name) do not.
    Solver full(room(false, true), dynamic_settings());
    full.solve();
    const double e = nrmse(corners_by_name(inc, kAll), corners_by_name(full, kAll));
    print_work("remove Box1", inc, work_since(inc, w0), full, e);
    EXPECT_LE(e, kTol);
    EXPECT_EQ(inc.stats().clusters, full.stats().clusters) << "the emptied collection's cluster is gone";
    EXPECT_LT(inc.stats().links, links_before);
    EXPECT_LT(work_since(inc, w0).evaluated, full.stats().links_evaluated);
    // Nothing of it is left in the link structure.
    const Hierarchy& h = inc.hierarchy();
    for (const Link& l : inc.links()) {
        if (l.dead) continue;
        ASSERT_FALSE(h.nodes[l.src].dead || h.nodes[l.rcv].dead);
        ASSERT_NE(h.nodes[l.src].object, 2);
        ASSERT_NE(h.nodes[l.rcv].object, 2);
    }
}

TEST(Topology, AddThenRemoveReturnsToTheOriginal) {
    Solver ref(room(true, false, true), dynamic_settings());
    ref.solve();
    Solver inc(room(true, false, true), dynamic_settings());
    inc.solve();
    const int id = inc.add_object(box2(1));
    inc.update();
    inc.remove_object(id);
    inc.update();
    const double e = nrmse(corners_by_name(inc, kAll), corners_by_name(ref, kAll));
    std::printf("[ figure ] add + remove round trip: NRMSE %.4f against the original; links %lld vs %lld\n", e,
                (long long)inc.stats().links, (long long)ref.stats().links);
    EXPECT_LE(e, kTol);
    // And back again, by removing an object and adding the same description (a new id).
    Solver inc2(room(true, true), dynamic_settings());
    inc2.solve();
    Solver ref2(room(true, true), dynamic_settings());
    ref2.solve();
    const ObjectDesc b1 = inc2.scene().objects()[2];
    inc2.remove_object(2);
    inc2.update();
    EXPECT_EQ(inc2.add_object(b1), 4);
    inc2.update();
    const double e2 = nrmse(corners_by_name(inc2, kAll), corners_by_name(ref2, kAll));
    std::printf("[ figure ] remove + add round trip: NRMSE %.4f against the original\n", e2);
    EXPECT_LE(e2, kTol);
}

TEST(Topology, AddAndRemoveInOneUpdate) {
    Solver inc(room(true, false, true), dynamic_settings());
    inc.solve();
    inc.add_object(box2(1));
    inc.remove_object(2);  // Box1
    inc.update();
    EXPECT_EQ(inc.stats().objects_added, 1);
    EXPECT_EQ(inc.stats().objects_removed, 1);
    // The samplers' compact surface table follows additions and removals.
    EXPECT_TRUE(inc.hierarchy().surface_geom_current());
    Solver full(room(false, true, true), dynamic_settings());
    full.solve();
    EXPECT_LE(nrmse(corners_by_name(inc, kAll), corners_by_name(full, kAll)), kTol);
}

TEST(Topology, UnclusteredScenes) {
    Settings st = dynamic_settings();
    st.use_clustering = false;
    st.error_threshold = 0.1;
    Solver inc(room(true, false, true), st);
    inc.solve();
    inc.add_object(box2(1));
    inc.update();
    Solver full(room(true, true), st);
    full.solve();
    const double add = nrmse(corners_by_name(inc, kAll), corners_by_name(full, kAll));
    inc.remove_object(2);
    inc.update();
    Solver full2(room(false, true), st);
    full2.solve();
    const double rem = nrmse(corners_by_name(inc, kAll), corners_by_name(full2, kAll));
    std::printf("[ figure ] unclustered: add NRMSE %.4f, remove NRMSE %.4f\n", add, rem);
    EXPECT_LE(add, kTol);
    EXPECT_LE(rem, kTol);
}

TEST(Topology, FurnaceStaysExact) {
    // A closed room and a box of the same rho and emission: B = E / (1 - rho) everywhere, with
    // the box added or removed.
    SceneDesc s = scenes::furnace_cube(0.5, 0.5, 3, 3.0);
    Solver solver(s, Settings::preset("MEDIUM"));
    solver.solve();
    SceneDesc t;
    scenes::add_box(t, "box", -1, {1, 1, 0.1}, {2, 1.5, 1}, 3, Rgb::all(0.5), Rgb::all(0.5));
    const int id = solver.add_object(t.objects()[0]);
    solver.update();
    for (int o : {0, id})
        for (const Node* n : front_leaves(solver, o)) EXPECT_NEAR(n->L.g, 1.0, 1e-3);
    solver.remove_object(id);
    solver.update();
    for (const Node* n : front_leaves(solver, 0)) EXPECT_NEAR(n->L.g, 1.0, 1e-3);
}

TEST(Topology, BadInputIsRefused) {
    Solver s(room(true, true), Settings::preset("DRAFT"));
    s.solve();
    ObjectDesc nan = box2(1);
    nan.vertices[3].y = std::nan("");
    EXPECT_THROW(s.add_object(nan), InputError);
    ObjectDesc bad_cluster = box2(1);
    bad_cluster.cluster = 17;
    EXPECT_THROW(s.add_object(bad_cluster), InputError);
    EXPECT_THROW(s.add_cluster("x", 42), InputError);
    EXPECT_THROW(s.remove_object(-1), InputError);
    EXPECT_THROW(s.remove_object(99), InputError);
    s.remove_object(3);
    EXPECT_THROW(s.remove_object(3), InputError) << "removing twice";
    s.update();
    EXPECT_THROW(s.remove_object(3), InputError) << "removing twice, after the update";
    const std::array<double, 16> m = {1, 0, 0, 1, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    EXPECT_THROW(s.move_object(3, m), InputError);
    EXPECT_THROW(s.set_emission(3, {Rgb::all(1.0)}), InputError);
    EXPECT_EQ(s.scene().objects().size(), 4u) << "a refused addition leaves no slot";
    for (float v : s.all_corner_radiance()) ASSERT_TRUE(std::isfinite(v));
}

TEST(Topology, ExtremeChangesStaySafe) {
    Solver s(room(true, true), Settings::preset("DRAFT"));
    s.solve();
    // An object of only zero-area polygons: no node, no crash.
    ObjectDesc flat = box2(1);
    for (Vec3& v : flat.vertices) v = {10, 10, 10};
    const int f = s.add_object(flat);
    s.update();
    EXPECT_EQ(s.corner_radiance(f).size(), flat.corner_count() * 3);
    // Far outside the scene: the frame changes, so the update solves in full and says so;
    // finite results (a vertex at 1e30 came to Embree as an invalid float ray: fuzzer finding).
    for (double at : {1e6, 1e30}) {
        ObjectDesc far = box2(1);
        for (Vec3& v : far.vertices) v.x += at;
        s.add_object(far);
        s.update();
        EXPECT_TRUE(has_warning(s, "scene's size")) << at;
        EXPECT_EQ(s.stats().update_fallback, UpdateFallback::scene_size) << at;
        for (float v : s.all_corner_radiance()) ASSERT_TRUE(std::isfinite(v));
    }
    // Added and removed before an update: nothing to do for it.
    const int g = s.add_object(box2(1));
    s.remove_object(g);
    s.update();
    EXPECT_TRUE(s.corner_radiance(g).empty());
    // The only emitter removed: dark, with the warning a dark scene gets.
    s.remove_object(1);
    s.update();
    for (float v : s.all_corner_radiance()) ASSERT_EQ(v, 0.f);
    // Everything removed.
    for (int o = 0; o < int(s.scene().objects().size()); ++o)
        if (!s.removed(o)) s.remove_object(o);
    s.update();
    EXPECT_TRUE(s.all_corner_radiance().empty());
    // And something added to the empty scene.
    SceneDesc t;
    scenes::add_grid(t, "lamp", -1, {Vec3{0, 0, 0}, Vec3{1, 0, 0}, Vec3{1, 1, 0}, Vec3{0, 1, 0}}, 1, 1, {}, Rgb::all(1.0));
    const int lamp = s.add_object(t.objects()[0]);
    s.update();
    for (float v : s.corner_radiance(lamp)) EXPECT_NEAR(v, 1.0, 1e-6);
}

TEST(Topology, AddingIntoAClosedPocketSolvesInFull) {
    // A closed box (its inner faces are a closed pocket: they exchange light with each other
    // only) gets an emitter inside it: new surfaces join that pocket, so the update solves in
    // full and says so.
    SceneDesc s;
    scenes::add_grid(s, "floor", -1, {Vec3{-5, -5, 0}, Vec3{5, -5, 0}, Vec3{5, 5, 0}, Vec3{-5, 5, 0}}, 4, 4, Rgb::all(0.5), {});
    scenes::add_grid(s, "lamp", -1, {Vec3{-1, -1, 4}, Vec3{-1, 1, 4}, Vec3{1, 1, 4}, Vec3{1, -1, 4}}, 1, 1, {}, Rgb::all(5.0));
    scenes::add_box(s, "crate", -1, {2, 2, 0.5}, {4, 4, 2.5}, 2, Rgb::all(0.5), {});
    Solver inc(s, Settings::preset("DRAFT"));
    inc.solve();
    SceneDesc t;
    scenes::add_box(t, "glow", -1, {2.5, 2.5, 1}, {3, 3, 1.5}, 1, Rgb::all(0.5), Rgb::all(3.0));
    inc.add_object(t.objects()[0]);
    inc.update();
    EXPECT_TRUE(has_warning(inc, "closed pocket"));
    EXPECT_EQ(inc.stats().update_fallback, UpdateFallback::pocket_added_removed);
    scenes::add_box(s, "glow", -1, {2.5, 2.5, 1}, {3, 3, 1.5}, 1, Rgb::all(0.5), Rgb::all(3.0));
    Solver full(s, Settings::preset("DRAFT"));
    full.solve();
    EXPECT_LE(nrmse(inc.all_corner_radiance(), full.all_corner_radiance()), 1e-6);
}

TEST(Topology, PointLightSceneAddEqualsFullSolve) {
    // Direct light of Blender lights is cached per leaf: an addition casts new shadows.
    auto scene = [](bool with_box) {
        SceneDesc s = room(true, with_box, true);
        s.add_light(point_light({150, 150, 200}, 4e4, 5));
        return s;
    };
    Solver inc(scene(false), dynamic_settings());
    inc.solve();
    inc.add_object(box2(1));
    inc.update();
    Solver full(scene(true), dynamic_settings());
    full.solve();
    const double e = nrmse(corners_by_name(inc, kAll), corners_by_name(full, kAll));
    std::printf("[ figure ] add Box2 under a point light: NRMSE %.4f\n", e);
    EXPECT_LE(e, kTol);
}

TEST(Topology, DeadLinksDoNotCountTowardTheLinkCap) {
    // Updates kill links (their slots stay); the max_links cap counts live links only. Counting
    // the dead ones stopped refinement after a few round trips: cluster links into the re-added
    // object stayed coarse and its top came out 50 % too bright (the full room at MEDIUM).
    Settings st = dynamic_settings();
    Solver probe(room(true, true), st);
    probe.solve();
    // Room for one solve and the history links the round trips keep alive (about 1.3x), not
    // for the dead links (over 1.2x more).
    st.max_links = int64_t(1.4 * double(probe.links().size()));
    Solver ref(room(true, true), st);
    ref.solve();
    ASSERT_FALSE(ref.stats().capped);
    Solver inc(room(true, true), st);
    inc.solve();
    int box1 = 2;
    for (int trip = 0; trip < 4; ++trip) {
        const ObjectDesc b1 = inc.scene().objects()[box1];
        inc.remove_object(box1);
        inc.update();
        box1 = inc.add_object(b1);
        inc.update();
    }
    int64_t dead = 0;
    for (const Link& l : inc.links()) dead += l.dead;
    EXPECT_GT(int64_t(inc.links().size()), st.max_links) << "the test needs more link slots than the cap";
    EXPECT_GT(dead, 0);
    EXPECT_FALSE(inc.stats().capped);
    const double e = nrmse(corners_by_name(inc, kAll), corners_by_name(ref, kAll));
    std::printf("[ figure ] 4 remove + add round trips under a tight link cap: NRMSE %.4f, %lld link slots (%lld dead), "
                "cap %lld\n", e, (long long)inc.links().size(), (long long)dead, (long long)st.max_links);
    EXPECT_LE(e, kTol);
}

TEST(Topology, MovingAnAddedObjectBeforeTheUpdate) {
    // Fuzzer finding (fuzz/seeds/regression_move_of_added_object): in a dark scene the update
    // solves in full and applied pending moves to a per-object array the addition had not grown
    // yet (UBSan: reference binding to null). The same sequence in a lit scene takes the
    // incremental path: the object is built where it was given, then moved.
    const std::array<double, 16> m = {1, 0, 0, 30, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    SceneDesc dark;
    scenes::add_box(dark, "room", -1, {0, 0, 0}, {300, 300, 250}, 2, Rgb::all(0.7), {}, true);
    Solver d(dark, Settings::preset("DRAFT"));
    d.solve();
    ObjectDesc lamp = box2(1);
    lamp.cluster = -1;
    lamp.emission.assign(lamp.polygon_count(), Rgb::all(1.0));
    const int id = d.add_object(lamp);
    d.move_object(id, m);
    d.update();
    for (float v : d.all_corner_radiance()) ASSERT_TRUE(std::isfinite(v));

    Solver inc(room(true, false, true), Settings::preset("DRAFT"));
    inc.solve();
    const int b = inc.add_object(box2(1));
    inc.move_object(b, m);
    inc.update();
    EXPECT_EQ(inc.stats().objects_added, 1);
    SceneDesc moved = room(true, false, true);
    ObjectDesc b2 = box2(1);
    for (Vec3& v : b2.vertices) v.x += 30;
    moved.add_object(b2);
    Solver full(moved, Settings::preset("DRAFT"));
    full.solve();
    EXPECT_LE(nrmse(corners_by_name(inc, kAll), corners_by_name(full, kAll)), kTol);
}

TEST(Topology, ManyAdditionsInOneUpdate) {
    // Several objects into one new collection, one more into a collection nested in it, and a
    // lone object, all in one update (the Blender gather test did this): each pair of them is
    // linked once. Making a pair twice (the new collection's self-link and an object's chain
    // both made it) transported light twice and the gathering diverged to inf.
    auto scene = [](bool with) {
        SceneDesc s = room(false, false);
        const int props = s.add_cluster("Props");
        const int inner = s.add_cluster("Inner", props);
        if (with) {
            scenes::add_box(s, "Box1", props, {84.4, 99.2, 0}, {144.4, 159.2, 100}, 2, Rgb{0.7, 0.3, 0.2}, {});
            // A closed, glowing inside (inward faces, rho 0.9): its faces exchange all their light,
            // so a doubled link inside it makes the gathering diverge.
            scenes::add_box(s, "Box2", props, {200, 200, 10}, {260, 250, 60}, 2, Rgb::all(0.9), Rgb::all(1.0), true);
            scenes::add_box(s, "Cube", inner, {40, 220, 0}, {80, 260, 40}, 2, Rgb{0.5, 0.5, 0.5}, {});
            scenes::add_box(s, "Lone", -1, {220, 40, 0}, {260, 80, 40}, 2, Rgb{0.6, 0.6, 0.2}, {});
        }
        return s;
    };
    Solver inc(scene(false), dynamic_settings());
    inc.solve();
    const SceneDesc all = scene(true);
    for (size_t o = 2; o < all.objects().size(); ++o) inc.add_object(all.objects()[o]);
    inc.update();
    EXPECT_EQ(inc.stats().objects_added, 4);
    Solver full(all, dynamic_settings());
    full.solve();
    const std::vector<std::string> names = {"room", "light", "Box1", "Box2", "Cube", "Lone"};
    const double e = nrmse(corners_by_name(inc, names), corners_by_name(full, names));
    std::printf("[ figure ] four objects added in one update (two collections, one nested): NRMSE %.4f, links %lld vs "
                "full %lld\n", e, (long long)inc.stats().links, (long long)full.stats().links);
    for (float v : inc.all_corner_radiance()) ASSERT_TRUE(std::isfinite(v));
    EXPECT_LE(e, kTol);
}
