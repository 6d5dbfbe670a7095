// Blender lights and world (lights.cpp): direct light against closed forms, the world as a
// uniform sky, refinement at shadow edges, incremental light changes, lighting-only output
// and the adaptive (leaf) mesh.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>

#include "test_util.h"

using namespace radiosity;
using namespace radiosity::testing;

namespace {

// A 4 x 4 floor at z = 0 (n x n quads), facing up, rho 0.5, no emission.
SceneDesc floor_scene(int n = 8) {
    SceneDesc s;
    scenes::add_grid(s, "floor", -1, {Vec3{-2, -2, 0}, Vec3{2, -2, 0}, Vec3{2, 2, 0}, Vec3{-2, 2, 0}}, n, n,
                     Rgb::all(0.5), Rgb{});
    return s;
}

// Corner positions of object 0 with their radiance.
std::vector<std::pair<Vec3, Rgb>> corners(const Solver& s, const std::vector<float>& v, int object = 0) {
    const ObjectDesc& o = s.scene().objects()[object];
    std::vector<std::pair<Vec3, Rgb>> out;
    for (size_t c = 0; c < o.corner_count(); ++c)
        out.push_back({o.vertices[o.corner_verts[c]], Rgb{v[3 * c], v[3 * c + 1], v[3 * c + 2]}});
    return out;
}

}  // namespace

TEST(Lights, PointLightOverAPlaneMatchesTheInverseSquareLaw) {
    SceneDesc s = floor_scene();
    const Vec3 lp{0.3, -0.2, 1.5};
    const double I = 100 / (4 * kPi);
    s.add_light(point_light(lp, I));
    Solver solver(s, Settings::preset("HIGH"));
    solver.solve();
    double num = 0, den = 0;
    for (const auto& [p, L] : corners(solver, solver.corner_radiance(0))) {
        Vec3 d = lp - p;
        double ref = 0.5 * I * (d.z / length(d)) / length2(d) / kPi;
        num += (L.r - ref) * (L.r - ref);
        den += ref * ref;
        EXPECT_NEAR(L.r, L.b, 1e-9);
    }
    // Corners carry the mean of the leaves around them: second-order close to the point value.
    EXPECT_LT(std::sqrt(num / den), 0.02);
}

TEST(Lights, SunAndSkyOnAnOpenPlaneAreExact) {
    SceneDesc s = floor_scene(2);
    LightDesc sun;
    sun.name = "sun";
    sun.type = LightDesc::Type::Sun;
    sun.direction = normalize(Vec3{0.5, 0, -1});
    sun.angle = 0.05;
    sun.intensity = Rgb{3, 2, 1};
    s.add_light(sun);
    LightDesc sky;
    sky.name = "world";
    sky.type = LightDesc::Type::Sky;
    sky.intensity = Rgb{0.2, 0.3, 0.4};
    s.add_light(sky);
    Solver solver(s, Settings::preset("MEDIUM"));
    solver.solve();
    const double cs = 1 / std::sqrt(1.25);
    // Nothing occludes: rho (S cos / pi + L_sky), up to the sun's finite disk (cos averaged
    // over a 0.05 rad disk differs by < 1e-3).
    for (const auto& [p, L] : corners(solver, solver.corner_radiance(0))) {
        (void)p;
        EXPECT_NEAR(L.r, 0.5 * (3 * cs / kPi + 0.2), 2e-3);
        EXPECT_NEAR(L.g, 0.5 * (2 * cs / kPi + 0.3), 2e-3);
        EXPECT_NEAR(L.b, 0.5 * (1 * cs / kPi + 0.4), 2e-3);
    }
}

TEST(Lights, ShadowEdgesRefineAndTheShadowIsDark) {
    // A small blocker between a point light and the floor: the floor refines around the
    // shadow and the leaves right under the blocker get no direct light.
    SceneDesc s = floor_scene(4);
    scenes::add_box(s, "blocker", -1, Vec3{-0.25, -0.25, 0.7}, Vec3{0.25, 0.25, 0.8}, 1, Rgb::all(0.0), Rgb{});
    s.add_light(point_light({0, 0, 1.5}, 10));
    Solver solver(s, Settings::preset("MEDIUM"));
    solver.solve();
    int leaves = 0;
    const Hierarchy& h = solver.hierarchy();
    for (const Node* n : front_leaves(solver, 0)) {
        ++leaves;
        const Vec3 c = n->center * h.unit + h.origin;  // world
        if (std::fabs(c.x) < 0.2 && std::fabs(c.y) < 0.2)
            EXPECT_LT(n->L.r, 1e-9) << "a leaf in the umbra is lit: centre " << n->center.x << " " << n->center.y
                                    << " " << n->center.z << " area " << n->area << " depth " << n->depth;
    }
    EXPECT_GT(leaves, 16 * 4);
    EXPECT_GT(solver.stats().elements, 16);
}

TEST(Lights, MovingAPointLightIncrementallyEqualsAFullSolve) {
    SceneDesc s = floor_scene(6);
    scenes::add_box(s, "box", -1, Vec3{0.2, 0.0, 0.0}, Vec3{1.0, 0.8, 0.8}, 3, Rgb{0.7, 0.35, 0.2}, Rgb{});
    s.add_light(point_light({-0.5, -0.3, 1.5}, 16, 0.1));
    Settings st = Settings::preset("HIGH");
    Solver inc(s, st);
    inc.solve();
    const std::vector<float> before = inc.corner_radiance(0);
    LightDesc moved = point_light({0.9, -0.6, 1.3}, 16, 0.1);
    inc.set_light(0, moved);
    inc.update();
    EXPECT_TRUE(inc.stats().mode_incremental);
    SceneDesc s2 = floor_scene(6);
    scenes::add_box(s2, "box", -1, Vec3{0.2, 0.0, 0.0}, Vec3{1.0, 0.8, 0.8}, 3, Rgb{0.7, 0.35, 0.2}, Rgb{});
    s2.add_light(moved);
    Solver full(s2, st);
    full.solve();
    // Both objects' corners together (measured 0.32 %, the box alone 0.37 %: where it meets
    // the floor the link hierarchies of an update and a full solve still differ a little).
    std::vector<float> a = inc.corner_radiance(0), b = full.corner_radiance(0);
    for (float x : inc.corner_radiance(1)) a.push_back(x);
    for (float x : full.corner_radiance(1)) b.push_back(x);
    const double e = nrmse(a, b);
    std::printf("[ figure ] incremental vs full NRMSE %.5f (box alone %.5f)\n", e,
                nrmse(inc.corner_radiance(1), full.corner_radiance(1)));
    EXPECT_LT(e, 0.005);
    EXPECT_GT(nrmse(before, full.corner_radiance(0)), 0.05);  // the move mattered
}

TEST(Lights, MovingAPointLightBesideABoxEqualsAFullSolve) {
    // The scene of tests/blender/test_lights.py: a moved point light goes through
    // the incremental path and equals a full solve within 0.5 % NRMSE. The error used to sit
    // at the box's foot, where the update kept the link and light refinement made for the old
    // light position (0.68 % on the first move, 0.84 % on the second, before settled links
    // were evaluated again, light splits coarsened top-down and a lit scene's first links
    // judged on the lamps' first bounce, as a full solve does). Measured: 0.26 %, 0.40 %.
    const Vec3 from{-0.5, -0.3, 1.5};
    for (const Vec3 to : {Vec3{0.9, -0.6, 1.3}, Vec3{-1.0, 1.0, 1.2}}) {
        const Settings st = Settings::preset("HIGH");
        Solver inc(scenes::point_light_box_on_floor(from), st);
        inc.solve();
        const int64_t evaluated_before = inc.stats().links_evaluated;
        LightDesc moved = inc.scene().lights()[0];
        moved.position = to;
        inc.set_light(0, moved);
        inc.update();
        EXPECT_TRUE(inc.stats().mode_incremental);
        Solver full(scenes::point_light_box_on_floor(to), st);
        full.solve();
        const double e = nrmse(inc.all_corner_radiance(), full.all_corner_radiance());
        const int64_t evaluated = inc.stats().links_evaluated - evaluated_before;
        std::printf("[ figure ] point light to (%g, %g, %g): incremental vs full NRMSE %.5f; elements %lld vs %lld, "
                    "links %lld vs %lld, links evaluated %lld vs %lld\n",
                    to.x, to.y, to.z, e, (long long)inc.stats().elements, (long long)full.stats().elements,
                    (long long)inc.stats().links, (long long)full.stats().links, (long long)evaluated,
                    (long long)full.stats().links_evaluated);
        EXPECT_LT(e, 0.005);
        // Incremental: the kept links are reused, not linked again from the root.
        EXPECT_LT(evaluated, full.stats().links_evaluated / 2);
        // The light's elements follow the light (splits for the old position merged back).
        // Within 15 %: since HIGH's threshold follows the receiver's light (threshold_floor),
        // the update keeps more elements than a full solve, its un-refinement judging on
        // radiance a full solve's rounds never see (3 % and 12 % more here). The corners agree
        // within 0.05 % NRMSE all the same.
        EXPECT_NEAR(double(inc.stats().elements), double(full.stats().elements), 0.15 * full.stats().elements);
    }
}

TEST(Lights, LightingOnlyIsRadianceWithoutAlbedoAndEmission) {
    SceneDesc s;
    scenes::add_grid(s, "floor", -1, {Vec3{-2, -2, 0}, Vec3{2, -2, 0}, Vec3{2, 2, 0}, Vec3{-2, 2, 0}}, 4, 4,
                     Rgb{0.6, 0.4, 0.2}, Rgb{0.1, 0.0, 0.0});
    scenes::add_grid(s, "wall", -1, {Vec3{-2, 2, 0}, Vec3{2, 2, 0}, Vec3{2, 2, 2}, Vec3{-2, 2, 2}}, 4, 4,
                     Rgb::all(0.5), Rgb{});
    s.add_light(point_light({0, 0, 1}, 5, 0.05));
    Solver solver(s, Settings::preset("MEDIUM"));
    solver.solve();
    const std::vector<float> L = solver.corner_radiance(0), E = solver.corner_irradiance(0);
    const double rho[3] = {0.6, 0.4, 0.2}, em[3] = {0.1, 0, 0};
    for (size_t i = 0; i < L.size(); ++i) EXPECT_NEAR(L[i], em[i % 3] + rho[i % 3] * E[i], 1e-5 + 1e-4 * L[i]);
}

TEST(Lights, LeafMeshIsTVertexFreeAndCarriesTheElements) {
    SceneDesc s = floor_scene(3);
    scenes::add_box(s, "blocker", -1, Vec3{-0.25, -0.25, 0.7}, Vec3{0.25, 0.25, 0.8}, 1, Rgb::all(0.2), Rgb{});
    s.add_light(point_light({0.1, 0, 1.5}, 10, 0.05));
    Solver solver(s, Settings::preset("MEDIUM"));
    solver.solve();
    LeafMesh m = solver.leaf_mesh(0, false);
    ASSERT_GT(m.loop_totals.size(), 9u);
    std::map<std::pair<int, int>, int> edges;
    size_t c = 0;
    double area = 0;
    for (size_t f = 0; f < m.loop_totals.size(); ++f) {
        const int n = m.loop_totals[f];
        Vec3 cross_sum;
        for (int k = 0; k < n; ++k) {
            int a = m.corner_verts[c + k], b = m.corner_verts[c + (k + 1) % n];
            edges[{std::min(a, b), std::max(a, b)}]++;
            cross_sum += cross(m.vertices[a], m.vertices[b]);
        }
        area += 0.5 * length(cross_sum);
        // The polygon's value is the solver's leaf at its centre.
        Vec3 ctr;
        for (int k = 0; k < n; ++k) ctr += m.vertices[m.corner_verts[c + k]] / n;
        Rgb r = solver.radiance_at(0, m.source_face[f], ctr);
        EXPECT_NEAR(r.r, m.values[f].r, 1e-12);
        c += size_t(n);
    }
    EXPECT_NEAR(area, 16.0, 1e-9);
    for (const auto& [e, count] : edges) {
        EXPECT_LE(count, 2);
        // No vertex strictly inside an edge.
        const Vec3 a = m.vertices[e.first], b = m.vertices[e.second];
        for (size_t v = 0; v < m.vertices.size(); ++v) {
            if (int(v) == e.first || int(v) == e.second) continue;
            Vec3 d = b - a;
            double t = dot(m.vertices[v] - a, d) / length2(d);
            if (t <= 1e-9 || t >= 1 - 1e-9) continue;
            ASSERT_GT(length(m.vertices[v] - (a + d * t)), 1e-9) << "T-vertex";
        }
    }
}

TEST(Lights, AnAreaLightObjectCastsNoShadow) {
    // A non-occluding one-sided emitter facing up under a lit plate: the plate above is lit
    // by it, and a point light above the plate still reaches the floor through the "light".
    SceneDesc s = floor_scene(2);
    ObjectDesc lamp;
    lamp.name = "area";
    lamp.vertices = {{-1, -1, 0.5}, {1, -1, 0.5}, {1, 1, 0.5}, {-1, 1, 0.5}};
    lamp.loop_starts = {0};
    lamp.loop_totals = {4};
    lamp.corner_verts = {0, 1, 2, 3};
    lamp.reflectance = {Rgb{}};
    lamp.emission = {Rgb::all(0.0)};
    lamp.two_sided = {0};
    lamp.occluder = false;
    s.add_object(lamp);
    s.add_light(point_light({0, 0, 1.5}, 10));
    Solver solver(s, Settings::preset("MEDIUM"));
    solver.solve();
    // The floor straight below gets the light as if the lamp polygon were not there.
    Rgb L = solver.radiance_at(0, 0, Vec3{-1.5, -1.5, 0});
    Vec3 d = Vec3{0, 0, 1.5} - Vec3{-1.5, -1.5, 0};
    EXPECT_GT(L.r, 0.5 * 0.5 * 10 * (d.z / length(d)) / length2(d) / kPi);
    Rgb C = solver.radiance_at(0, 3, Vec3{0.5, 0.5, 0});
    Vec3 dc = Vec3{0, 0, 1.5} - Vec3{0.5, 0.5, 0};
    EXPECT_GT(C.r, 0.9 * 0.5 * 10 * (dc.z / length(dc)) / length2(dc) / kPi);
}
