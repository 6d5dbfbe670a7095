// Numerical stability at the extremes and bad input. Every case either gives the
// right answer or a clear error: never a crash, a hang, or a NaN/inf in the output.
#include <gtest/gtest.h>
#include <malloc.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <limits>
#include <string>

#include "radiosity/random.h"
#include "test_util.h"

using namespace radiosity;
using namespace radiosity::testing;

namespace {

// One object from explicit polygons (vertex index lists); one material for all of them.
ObjectDesc make_object(const std::string& name, int cluster, std::vector<Vec3> verts,
                       const std::vector<std::vector<int>>& faces, Rgb rho, Rgb emission, bool two_sided = true) {
    ObjectDesc o;
    o.name = name;
    o.cluster = cluster;
    o.vertices = std::move(verts);
    for (const auto& f : faces) {
        o.loop_starts.push_back(int32_t(o.corner_verts.size()));
        o.loop_totals.push_back(int32_t(f.size()));
        o.corner_verts.insert(o.corner_verts.end(), f.begin(), f.end());
        o.reflectance.push_back(rho);
        o.emission.push_back(emission);
        o.two_sided.push_back(two_sided);
    }
    return o;
}

// The invariants every solved scene must keep, whatever its input: every corner value and
// every live node radiance finite and non-negative, and no radiance above what a closed
// scene of the brightest emitter and the largest reflectance could reach, E_max / (1 - rho_max)
// (slack for the discretisation: cluster links and closure scaling are approximate).
void expect_sane(const Solver& s, const std::string& what) {
    double e_max = 0, rho_max = 0;
    for (const ObjectDesc& o : s.scene().objects())
        for (size_t f = 0; f < o.polygon_count(); ++f) {
            e_max = std::max(e_max, o.emission[f].max());
            rho_max = std::max(rho_max, o.reflectance[f].max());
        }
    const double bound = 1.1 * e_max / (1.0 - rho_max);
    size_t bad = 0, above = 0;
    double worst = 0;
    for (size_t o = 0; o < s.scene().objects().size(); ++o) {
        auto c = s.corner_radiance(int(o));
        ASSERT_EQ(c.size(), 3 * s.scene().objects()[o].corner_count()) << what;
        for (float v : c) {
            if (!std::isfinite(v) || v < 0) ++bad;
            else if (v > bound) ++above, worst = std::max(worst, double(v));
        }
    }
    for (const Node& n : s.hierarchy().nodes) {
        if (n.dead) continue;
        if (!finite(n.L) || n.L.r < 0 || n.L.g < 0 || n.L.b < 0) ++bad;
    }
    EXPECT_EQ(bad, 0u) << what << ": non-finite or negative radiance";
    EXPECT_EQ(above, 0u) << what << ": " << above << " corners above E_max/(1-rho_max) = " << bound << ", worst "
                         << worst;
    const Stats& st = s.stats();
    EXPECT_TRUE(std::isfinite(st.residual)) << what;
}

// A 3 x 3 x 2.5 room with a ceiling light: the ordinary scene the extreme cases vary.
SceneDesc lit_room(double light_gap = 0.1, int n = 3) {
    SceneDesc s;
    scenes::add_box(s, "room", -1, {0, 0, 0}, {3, 3, 2.5}, n, Rgb::all(0.7), {}, true);
    const double z = 2.5 - light_gap;
    scenes::add_grid(s, "light", -1, {Vec3{1.25, 1.25, z}, Vec3{1.25, 1.75, z}, Vec3{1.75, 1.75, z}, Vec3{1.75, 1.25, z}},
                     1, 1, {}, Rgb::all(10.0));
    return s;
}

// Point form factor from a point at height h under the centre of an a x b emitter (NOTES.md).
double on_axis_factor(double a, double b, double h) {
    auto f = [](double x, double y) {
        return (x / std::sqrt(1 + x * x) * std::atan(y / std::sqrt(1 + x * x)) +
                y / std::sqrt(1 + y * y) * std::atan(x / std::sqrt(1 + y * y))) /
               (2 * kPi);
    };
    return 4 * f(a / (2 * h), b / (2 * h));
}

}  // namespace

// ---------------------------------------------------------------------------------------
// Physics extremes
// ---------------------------------------------------------------------------------------

TEST(Extremes, FurnaceNearOneWithPresetCapsReportsItsResidual) {
    // rho = 0.999: Jacobi contracts by 0.999 per sweep, so the preset iteration cap may stop
    // the solve before the tolerance. Then the solver must say so, and the residual it
    // reports must cover the error actually left (an honest estimate, not a silent stop).
    const double rho = 0.999, e = 1.0, exact = e / (1 - rho);
    Settings settings = Settings::preset("DRAFT");  // DRAFT: thousands of sweeps, each cheap
    settings.threads = 1;  // over a few dozen elements thread start-up would dominate
    Solver s(scenes::furnace_cube(rho, e, 1), settings);
    s.solve();
    expect_sane(s, "furnace 0.999");
    double worst = 0;
    for (float v : s.corner_radiance(0)) worst = std::max(worst, std::fabs(v - exact) / exact);
    const Stats& st = s.stats();
    std::printf("[ figure ] furnace rho=0.999 DRAFT: worst corner error %.4f %%, iterations %d, capped %d, residual %.3g "
                "(x L_ref %.4g)\n",
                100 * worst, st.iterations, int(st.iteration_capped), st.residual, s.reference_radiance());
    if (st.iteration_capped) {
        // The residual is relative to L_ref; the actual error must be inside it.
        EXPECT_GT(st.residual, 0.0);
        EXPECT_LE(worst * exact, 1.5 * st.residual * s.reference_radiance()) << "residual under-reports the error";
    } else {
        EXPECT_LE(worst, 0.005);
    }
}

TEST(Extremes, FurnaceNearOneConvergesWithinHalfAPercent) {
    // The target: within 0.5 % of E / (1 - rho) once the iteration may run long enough.
    const double rho = 0.999, e = 1.0, exact = e / (1 - rho);
    Settings st = Settings::preset("DRAFT");
    st.tolerance = 1e-4;  // ~13k Jacobi sweeps at rho = 0.999; DRAFT keeps each one cheap
    st.max_iterations = 40000;
    st.threads = 1;
    Solver s(scenes::furnace_cube(rho, e, 1), st);
    s.solve();
    expect_sane(s, "furnace 0.999 long");
    double worst = 0;
    for (float v : s.corner_radiance(0)) worst = std::max(worst, std::fabs(v - exact) / exact);
    for (const Node* n : front_leaves(s, 0)) worst = std::max(worst, std::fabs(n->L.g - exact) / exact);
    EXPECT_FALSE(s.stats().iteration_capped) << "iterations " << s.stats().iterations;
    EXPECT_LE(worst, 0.005) << "iterations " << s.stats().iterations << " residual " << s.stats().residual;
}

TEST(Extremes, ReflectanceOneOrAboveIsRejected) {
    // Documented in scene.h/scene.cpp: reflectance must lie in [0, 1) (the add-on clamps to
    // 0.999 before it gets here); with emission the system has no finite solution.
    for (double rho : {1.0, 1.0000001, 1.5, 1e300}) {
        SceneDesc s;
        try {
            s.add_object(make_object("Glow", -1, {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}}, {{0, 1, 2}}, Rgb{0.5, rho, 0.5},
                                     Rgb::all(1.0)));
            ADD_FAILURE() << "rho " << rho << " accepted";
        } catch (const InputError& e) {
            std::string m = e.what();
            EXPECT_NE(m.find("Glow"), std::string::npos) << m;
            EXPECT_NE(m.find("reflectance"), std::string::npos) << m;
        }
    }
    // And through the dynamic API.
    Solver s(lit_room(), Settings::preset("DRAFT"));
    s.solve();
    EXPECT_THROW(s.set_reflectance(0, {Rgb{0.2, 1.0, 0.2}}), InputError);
    EXPECT_THROW(s.set_reflectance(0, {Rgb::all(std::nan(""))}), InputError);
}

TEST(Extremes, ZeroReflectanceEverywhere) {
    // Nothing reflects: emitters show their emission, every other surface is exactly black.
    SceneDesc sc;
    scenes::add_box(sc, "room", -1, {0, 0, 0}, {3, 3, 2.5}, 3, Rgb::all(0.0), {}, true);
    scenes::add_grid(sc, "light", -1, {Vec3{1, 1, 2.4}, Vec3{1, 2, 2.4}, Vec3{2, 2, 2.4}, Vec3{2, 1, 2.4}}, 1, 1, {},
                     Rgb{4, 5, 6});
    Solver s(sc, Settings::preset("MEDIUM"));
    s.solve();
    expect_sane(s, "rho 0");
    for (float v : s.corner_radiance(0)) EXPECT_EQ(v, 0.f);
    auto light = s.corner_radiance(1);
    for (size_t i = 0; i < light.size(); i += 3) {
        EXPECT_FLOAT_EQ(light[i], 4.f);
        EXPECT_FLOAT_EQ(light[i + 1], 5.f);
        EXPECT_FLOAT_EQ(light[i + 2], 6.f);
    }
}

TEST(Extremes, EmissionScalesLinearlyFromMicroToMega) {
    // The oracle's threshold is relative to a reference radiance, so scaling every emitter
    // must scale every output by exactly the same factor (same refinement, same rays).
    auto solve = [](double k) {
        SceneDesc s = scenes::cornell_box(3);
        for (ObjectDesc& o : s.objects_mut())
            for (Rgb& e : o.emission) e *= k;
        Solver solver(s, Settings::preset("DRAFT"));
        solver.solve();
        expect_sane(solver, "emission x " + std::to_string(k));
        return solver.all_corner_radiance();
    };
    const auto ref = solve(1.0);
    double peak = 0;
    for (float v : ref) peak = std::max(peak, double(v));
    for (double k : {1e-6, 1e6}) {
        const auto x = solve(k);
        ASSERT_EQ(x.size(), ref.size());
        double worst = 0;
        for (size_t i = 0; i < x.size(); ++i) {
            // Relative per corner; corners at (near) zero compared against 1e-9 of the peak.
            double r = std::fabs(x[i] / k - ref[i]) / std::max(double(ref[i]), 1e-9 * peak);
            worst = std::max(worst, r);
        }
        EXPECT_LE(worst, 1e-4) << "emission x " << k;
    }
}

TEST(Extremes, EmissionBeyondFloatRangeNeverGivesInf) {
    // The output is float32; a finite double emission above FLT_MAX (Python passes colour x
    // strength as doubles) must be rejected, or give finite output -- never inf.
    for (double e : {1e38, 1e39, 1e200}) {
        SceneDesc s;
        scenes::add_grid(s, "floor", -1, {Vec3{0, 0, 0}, Vec3{1, 0, 0}, Vec3{1, 1, 0}, Vec3{0, 1, 0}}, 2, 2, Rgb::all(0.5),
                         {});
        try {
            scenes::add_grid(s, "sun", -1, {Vec3{0, 0, 1}, Vec3{0, 1, 1}, Vec3{1, 1, 1}, Vec3{1, 0, 1}}, 1, 1, {},
                             Rgb::all(e));
        } catch (const InputError& err) {
            EXPECT_NE(std::string(err.what()).find("sun"), std::string::npos) << err.what();
            continue;  // rejected with a clear error: fine
        }
        Solver solver(s, Settings::preset("DRAFT"));
        solver.solve();
        for (float v : solver.all_corner_radiance()) EXPECT_TRUE(std::isfinite(v)) << "emission " << e << " gave " << v;
    }
    // The same through set_emission on a solved scene.
    Solver s(lit_room(), Settings::preset("DRAFT"));
    s.solve();
    try {
        s.set_emission(1, {Rgb::all(1e39)});
        s.update();
    } catch (const InputError&) {
    }
    for (float v : s.all_corner_radiance()) EXPECT_TRUE(std::isfinite(v)) << "set_emission 1e39 gave " << v;
}

TEST(Extremes, NoEmitterAnywhereGivesZerosAndAWarning) {
    // A furnished room with every light at zero (the furnace case is in test_solver.cpp).
    SceneDesc sc = lit_room();
    sc.objects_mut()[1].emission.assign(1, Rgb{});
    Solver s(sc, Settings::preset("MEDIUM"));
    s.solve();
    expect_sane(s, "no emitter");
    EXPECT_TRUE(s.stats().no_emitters);
    ASSERT_FALSE(s.stats().warnings.empty());
    EXPECT_NE(s.stats().warnings[0].find("emitter"), std::string::npos) << s.stats().warnings[0];
    for (float v : s.all_corner_radiance()) EXPECT_EQ(v, 0.f);
}

TEST(Extremes, SwitchingOffEveryLightByUpdateGivesZeros) {
    // The dynamic path: the last light goes dark through set_emission + update. The
    // reference radiance becomes 0; the update must neither refine everything (a zero
    // threshold) nor leave a decaying remnant of the old light.
    Solver s(lit_room(), Settings::preset("DRAFT"));
    s.solve();
    const int64_t elements_before = s.stats().element_nodes;
    s.set_emission(1, {Rgb{}});
    s.update();
    expect_sane(s, "lights off");
    EXPECT_EQ(s.stats().update_fallback, UpdateFallback::no_light);
    double peak = 0;
    for (float v : s.all_corner_radiance()) peak = std::max(peak, double(v));
    EXPECT_EQ(peak, 0.0) << "light left after switching every emitter off";
    EXPECT_LE(s.stats().element_nodes, elements_before) << "switching the light off refined the scene";
    // And back on: the same as a fresh solve.
    s.set_emission(1, {Rgb::all(10.0)});
    s.update();
    Solver fresh(lit_room(), Settings::preset("DRAFT"));
    fresh.solve();
    EXPECT_LE(nrmse(s.all_corner_radiance(), fresh.all_corner_radiance()), 0.03);
}

TEST(Extremes, LightSwitchedOnAfterADarkSolve) {
    // solve() makes no links when nothing emits; an update that turns a light on must
    // still light the room, as a fresh solve does.
    SceneDesc dark = lit_room();
    dark.objects_mut()[1].emission.assign(1, Rgb{});
    Solver s(dark, Settings::preset("DRAFT"));
    s.solve();
    ASSERT_TRUE(s.stats().no_emitters);
    s.set_emission(1, {Rgb::all(10.0)});
    s.update();
    expect_sane(s, "switched on");
    Solver fresh(lit_room(), Settings::preset("DRAFT"));
    fresh.solve();
    EXPECT_LE(nrmse(s.all_corner_radiance(), fresh.all_corner_radiance()), 0.03);
    EXPECT_GT(object_front_radiance(s, 0).g, 0.5 * object_front_radiance(fresh, 0).g) << "the room stayed dark";
}

TEST(Extremes, SceneScaleAndOffsetDoNotMatter) {
    // 1e-4, 1 and 1e4 times the Cornell box, and the box 1e6 away from the origin.
    auto solve = [](double k, Vec3 offset) {
        SceneDesc s = scenes::cornell_box(3);
        for (ObjectDesc& o : s.objects_mut())
            for (Vec3& v : o.vertices) v = v * k + offset;
        // Corner points at a step relative to the scene (Cycles' own step is in world units).
        Settings st = Settings::preset("DRAFT");
        st.cycles_corner_points = false;
        Solver solver(s, st);
        solver.solve();
        expect_sane(solver, "scale " + std::to_string(k));
        return solver.all_corner_radiance();
    };
    const auto ref = solve(1.0, {});
    double mean = 0;
    for (float v : ref) mean += v / ref.size();
    auto worst_corner = [&](const std::vector<float>& x) {
        double worst = 0;
        for (size_t i = 0; i < x.size(); ++i)
            worst = std::max(worst, std::fabs(double(x[i]) - ref[i]) / std::max(double(ref[i]), 1e-3 * mean));
        return worst;
    };
    // Scale alone maps to bit-identical internal geometry (hierarchy.h): every corner agrees.
    for (double k : {1e-4, 1e4}) EXPECT_LE(worst_corner(solve(k, {})), 1e-3) << "scale " << k;
    // 3e6 away, the input itself is rounded (ulp 5e-10 m): no longer bit-identical, so
    // refinement tie-breaks may differ; the solution must still agree as a whole.
    const auto far = solve(1.0, {1e6, -2e6, 3e6});
    std::printf("[ figure ] Cornell box 3e6 from the origin (DRAFT): NRMSE %.4f, worst corner %.3f\n", nrmse(far, ref),
                worst_corner(far));
    EXPECT_LE(nrmse(far, ref), 0.03);
}

TEST(Extremes, OneHugeAndManyTinyObjects) {
    // A 100 m floor under a 10 m light, and 100 cubes of 1 mm floating 1 cm above it
    // (size ratio 1e5). A cube's top sees the light as the floor below it does.
    SceneDesc sc;
    scenes::add_grid(sc, "floor", -1, {Vec3{-50, -50, 0}, Vec3{50, -50, 0}, Vec3{50, 50, 0}, Vec3{-50, 50, 0}}, 4, 4,
                     Rgb::all(0.5), {});
    scenes::add_grid(sc, "light", -1, {Vec3{-5, -5, 10}, Vec3{-5, 5, 10}, Vec3{5, 5, 10}, Vec3{5, -5, 10}}, 1, 1, {},
                     Rgb::all(10.0), false);
    Rng rng(7);
    std::vector<Vec3> where;
    for (int i = 0; i < 100; ++i) {
        Vec3 c{rng.next() * 40 - 20, rng.next() * 40 - 20, 0.01};
        int cl = sc.add_cluster("grain" + std::to_string(i));
        scenes::add_box(sc, "grain" + std::to_string(i), cl, c, c + Vec3{1e-3, 1e-3, 1e-3}, 1, Rgb::all(0.5), {});
        where.push_back(c);
    }
    Solver s(sc, Settings::preset("MEDIUM"));
    s.solve();
    expect_sane(s, "huge + tiny");
    EXPECT_EQ(s.stats().skipped_polygons, 0);
    // Reference: the analytic value at the top's centre, rho x L_e x F(point -> light) (the
    // top sees the light and nothing else). The floor's leaf below it was the reference
    // once, but that is an average over a leaf metres wide, which a coarser threshold widens.
    const Poly light = quad({-5, -5, 10}, {-5, 5, 10}, {5, 5, 10}, {5, -5, 10});
    double worst = 0;
    for (int i = 0; i < 100; ++i) {
        const int obj = 2 + i;
        // Face 1 of add_box is +z (the top).
        const Vec3 centre = where[i] + Vec3{5e-4, 5e-4, 1e-3};
        const Rgb top = s.radiance_at(obj, 1, centre);
        const double exact = 0.5 * 10 * point_polygon_form_factor(centre, {0, 0, 1}, light, light.normal());
        worst = std::max(worst, std::fabs(top.g - exact) / exact);
    }
    std::printf("[ figure ] 1 mm cubes on a 100 m floor: worst top vs the analytic value %.3f %%\n", 100 * worst);
    EXPECT_LE(worst, 0.01);
}

// ---------------------------------------------------------------------------------------
// Geometry extremes
// ---------------------------------------------------------------------------------------

TEST(Extremes, SliverTrianglesOfAspectOneMillion) {
    // A unit plate: one sliver (1 x 1e-6) across the middle and two quads either side; a
    // light above. A plane does not light itself, so every leaf's radiance is rho * L_e times
    // its own form factor to the light -- the sliver's included. A 1 m x 1 um emitting sliver
    // ("wire") must add (almost) nothing, finitely.
    const double w = 1e-6;
    std::vector<Vec3> v = {{0, 0, 0}, {1, 0, 0}, {1, 0.5, 0}, {0, 0.5, 0}, {1, 0.5 + w, 0}, {1, 1, 0}, {0, 1, 0}};
    SceneDesc sc;
    sc.add_object(make_object("plate", -1, v, {{0, 1, 2, 3}, {3, 2, 4}, {3, 4, 5, 6}}, Rgb::all(0.5), {}));
    const Poly light = quad({0.25, 0.25, 1}, {0.25, 0.75, 1}, {0.75, 0.75, 1}, {0.75, 0.25, 1});
    scenes::add_grid(sc, "light", -1, {light.v[0], light.v[1], light.v[2], light.v[3]}, 1, 1, {}, Rgb::all(10.0), false);
    scenes::add_grid(sc, "wire", -1, {Vec3{0, 0.2, 0.5}, Vec3{0, 0.2 + w, 0.5}, Vec3{1, 0.2 + w, 0.5}, Vec3{1, 0.2, 0.5}},
                     1, 1, {}, Rgb::all(10.0), false);
    Solver s(sc, Settings::preset("HIGH"));
    s.solve();
    expect_sane(s, "slivers");
    const Hierarchy& h = s.hierarchy();
    double worst = 0, sliver_worst = 0;
    for (const Primitive& p : h.prims) {
        if (p.object != 0) continue;
        std::vector<int> st{h.surfaces[p.front].root};
        while (!st.empty()) {
            const Node& n = h.nodes[st.back()];
            st.pop_back();
            for (int c : n.children) st.push_back(c);
            if (!n.children.empty()) continue;
            // The leaf's exact value by the same cubature, in world units (the internal frame
            // is a similarity, form factors are unchanged).
            Poly wp = n.poly;
            for (int k = 0; k < wp.n; ++k) wp.v[k] = wp.v[k] * h.unit + h.origin;
            double F = 0;
            Cubature cub = cubature(wp);
            for (int j = 0; j < cub.n; ++j) F += cub.w[j] * point_polygon_form_factor(cub.p[j], n.normal, light, light.normal());
            const double exact = 0.5 * 10 * F, err = std::fabs(n.L.g - exact) / std::max(exact, 1e-3);
            worst = std::max(worst, err);
            if (p.face == 1) sliver_worst = std::max(sliver_worst, err);
        }
    }
    EXPECT_LE(worst, 0.02) << "sliver leaves " << sliver_worst;
    // The sliver stays one element (its area is below the minimum) while it spans 1 m of a
    // varying light; its corners meet the quads' there. Printed, not asserted: a limit of
    // area-based refinement, not a failure.
    auto c = s.corner_radiance(0);
    const double exact_c = 0.5 * 10 * point_polygon_form_factor({1, 0.5, 0}, {0, 0, 1}, light, light.normal());
    std::printf("[ figure ] sliver plate: corner at (1, 0.5) %.4f vs exact %.4f\n", c[3 * 2 + 1], exact_c);
}

TEST(Extremes, ZeroAreaFacesAreSkippedAndTakeTheirNeighboursValue) {
    // Documented (hierarchy.h, Stats::skipped_polygons): zero-area polygons are skipped and
    // their corners take the value of the faces sharing their vertices.
    std::vector<Vec3> v = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5, 0, 0}, {2, 2, 0}};
    SceneDesc sc;
    sc.add_object(make_object("plate", -1, v,
                              {{0, 1, 2, 3},  // a real quad
                               {0, 4, 1},     // collinear
                               {2, 2, 2},     // one point
                               {1, 2, 2, 1},  // a quad folded onto an edge
                               {5, 5, 5}},    // one point away from everything
                              Rgb::all(0.5), {}));
    scenes::add_grid(sc, "light", -1, {Vec3{0.25, 0.25, 1}, Vec3{0.25, 0.75, 1}, Vec3{0.75, 0.75, 1}, Vec3{0.75, 0.25, 1}},
                     1, 1, {}, Rgb::all(10.0), false);
    Solver s(sc, Settings::preset("MEDIUM"));
    s.solve();
    expect_sane(s, "zero-area faces");
    EXPECT_EQ(s.stats().skipped_polygons, 4);
    auto c = s.corner_radiance(0);
    // The collinear triangle's corners on the quad's vertices 0 and 1 take the quad's value.
    EXPECT_FLOAT_EQ(c[3 * 4 + 1], c[3 * 0 + 1]);
    EXPECT_FLOAT_EQ(c[3 * 6 + 1], c[3 * 1 + 1]);
    EXPECT_GT(c[3 * 0 + 1], 0.f);
    // Vertex 4 belongs to no real face (it lies on the quad's edge, but shares no vertex
    // with it), nor does the isolated point: 0, not NaN.
    EXPECT_EQ(c[3 * 5 + 1], 0.f);
    for (int k = 14; k < 17; ++k) EXPECT_EQ(c[3 * k + 1], 0.f);
}

TEST(Extremes, DuplicateAndOverlappingCoplanarFaces) {
    // Z-fighting: the same plate three times (twice in one object, once in another) and a
    // coplanar overlapping shifted copy, under a one-sided light. Coplanar faces exchange no
    // light and do not shadow each other: every leaf of every copy gets exactly rho * L_e
    // times its own form factor to the light.
    auto plate = [](const std::string& name, double dx, int copies) {
        std::vector<Vec3> v = {{dx, 0, 0}, {dx + 1, 0, 0}, {dx + 1, 1, 0}, {dx, 1, 0}};
        std::vector<std::vector<int>> f(copies, {0, 1, 2, 3});
        return make_object(name, -1, v, f, Rgb::all(0.5), {});
    };
    const Poly light = quad({0, 0, 1}, {0, 1, 1}, {1.5, 1, 1}, {1.5, 0, 1});
    SceneDesc dup;
    dup.add_object(plate("a", 0, 2));
    dup.add_object(plate("b", 0, 1));
    dup.add_object(plate("c", 0.5, 1));
    scenes::add_grid(dup, "light", -1, {light.v[0], light.v[1], light.v[2], light.v[3]}, 1, 1, {}, Rgb::all(10.0), false);
    Solver s(dup, Settings::preset("MEDIUM"));
    s.solve();
    expect_sane(s, "duplicates");
    const Hierarchy& h = s.hierarchy();
    for (int obj = 0; obj < 3; ++obj) {
        double worst = 0;
        int leaves = 0;
        for (const Node* n : front_leaves(s, obj)) {
            Poly wp = n->poly;
            for (int k = 0; k < wp.n; ++k) wp.v[k] = wp.v[k] * h.unit + h.origin;
            double F = 0;
            Cubature cub = cubature(wp);
            for (int j = 0; j < cub.n; ++j) F += cub.w[j] * point_polygon_form_factor(cub.p[j], n->normal, light, light.normal());
            worst = std::max(worst, std::fabs(n->L.g - 0.5 * 10 * F) / (0.5 * 10 * F));
            ++leaves;
        }
        EXPECT_GT(leaves, 0);
        EXPECT_LE(worst, 0.01) << "object " << obj;
    }
}

TEST(Extremes, FacesTouchingAtACornerOnly) {
    // A floor square and a wall square meeting at a single vertex (kernel singular there),
    // compared with the same pair 1 mm apart: nothing may blow up at the contact.
    auto scene = [](double gap) {
        SceneDesc sc;
        sc.add_object(make_object("floor", -1, {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, {{0, 1, 2, 3}},
                                  Rgb::all(0.6), {}));
        // The wall stands in the plane x = 1 + gap, spanning y in [1 + gap, 2]: it touches the
        // floor only at (1, 1, 0) when gap = 0.
        const double g = gap;
        sc.add_object(make_object("wall", -1, {{1 + g, 1 + g, 0}, {1 + g, 2, 0}, {1 + g, 2, 1}, {1 + g, 1 + g, 1}},
                                  {{0, 1, 2, 3}}, Rgb::all(0.6), {}));
        scenes::add_grid(sc, "light", -1, {Vec3{0, 0, 2}, Vec3{0, 2, 2}, Vec3{2, 2, 2}, Vec3{2, 0, 2}}, 1, 1, {},
                         Rgb::all(5.0), false);
        return sc;
    };
    Solver a(scene(0), Settings::preset("HIGH"));
    a.solve();
    expect_sane(a, "corner contact");
    Solver b(scene(1e-3), Settings::preset("HIGH"));
    b.solve();
    EXPECT_LE(nrmse(a.all_corner_radiance(), b.all_corner_radiance()), 0.02);
}

TEST(Extremes, TJunctionsGiveContinuousCorners) {
    // A 2 x 1 floor: one unit quad on the left, two half quads on the right whose shared
    // vertex (1, 0.5) lies on the left quad's edge. Under a large distant light the floor is
    // lit almost uniformly; the T-vertex must agree with the rest.
    std::vector<Vec3> v = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {2, 0, 0}, {2, 0.5, 0}, {1, 0.5, 0}, {2, 1, 0}};
    SceneDesc sc;
    sc.add_object(make_object("floor", -1, v, {{0, 1, 2, 3}, {1, 4, 5, 6}, {6, 5, 7, 2}}, Rgb::all(0.5), {}));
    scenes::add_grid(sc, "sky", -1, {Vec3{-20, -20, 30}, Vec3{-20, 20, 30}, Vec3{20, 20, 30}, Vec3{20, -20, 30}}, 1, 1,
                     {}, Rgb::all(1.0), false);
    Solver s(sc, Settings::preset("HIGH"));
    s.solve();
    expect_sane(s, "T-junction");
    auto c = s.corner_radiance(0);
    double lo = 1e300, hi = 0;
    for (size_t i = 1; i < c.size(); i += 3) lo = std::min(lo, double(c[i])), hi = std::max(hi, double(c[i]));
    EXPECT_GT(lo, 0);
    EXPECT_LE((hi - lo) / hi, 0.02) << "min " << lo << " max " << hi;
}

TEST(Extremes, InvertedNormalsStillBounceLight) {
    // Surfaces are two-sided: flipping the floor's winding changes which side is output
    // (the side the normal points to, as in Cycles), not the light in the room.
    auto solve = [](bool flip) {
        SceneDesc sc = lit_room();
        if (flip) {
            ObjectDesc& room = sc.objects_mut()[0];
            // add_box emits -z first: the floor's 9 quads are polygons 0..8.
            for (int f = 0; f < 9; ++f)
                std::reverse(room.corner_verts.begin() + room.loop_starts[f],
                             room.corner_verts.begin() + room.loop_starts[f] + room.loop_totals[f]);
        }
        auto s = std::make_unique<Solver>(sc, Settings::preset("MEDIUM"));
        s->solve();
        expect_sane(*s, flip ? "flipped floor" : "floor");
        return s;
    };
    auto a = solve(false), b = solve(true);
    // The room side of the floor: the front in a, the back in b.
    auto room_side = [](const Solver& s, bool back) {
        const Hierarchy& h = s.hierarchy();
        double acc = 0, area = 0;
        for (const Primitive& p : h.prims) {
            if (p.object != 0 || p.face >= 9) continue;
            const Node& n = h.nodes[h.surfaces[back ? p.back : p.front].root];
            acc += n.L.g * n.area;
            area += n.area;
        }
        return acc / area;
    };
    double fa = room_side(*a, false), fb = room_side(*b, true);
    EXPECT_NEAR(fb, fa, 0.01 * fa);
    // The flipped floor's output side faces the void below the room: black, up to the
    // leak of oriented cluster links through the room's own walls (measured 0.7 %).
    auto cb = b->corner_radiance(0);
    double leak = 0;
    for (int c = 0; c < 9 * 4 * 3; ++c) leak = std::max(leak, double(cb[c]));
    std::printf("[ figure ] outside of a closed room's floor: %.3f %% of the inside\n", 100 * leak / fa);
    EXPECT_LE(leak, 0.02 * fa);
    // Walls and ceiling unchanged.
    auto ca = a->corner_radiance(0);
    std::vector<float> wa(ca.begin() + 9 * 12, ca.end()), wb(cb.begin() + 9 * 12, cb.end());
    EXPECT_LE(nrmse(wb, wa), 0.01);
}

// Was 3.57 (MEDIUM) against >= 6.65: the closure correction summed at the leaf over the
// light the couplings of its ancestors' links too, whose visibility was estimated over the
// whole ancestor (~2 in all), and scaled the leaf by ~0.5. Closure-driven refinement
// (refinement.cpp) now splits those ancestor links toward the leaf.
TEST(Extremes, LightOneMillimetreUnderTheCeilingLightsTheCeiling) {
    // Emission leaves both sides of a face: the ceiling right above the light gets almost
    // the full hemisphere of it (F -> 1 as the gap -> 0).
    Solver s(lit_room(1e-3), Settings::preset("MEDIUM"));
    s.solve();
    expect_sane(s, "light 1 mm under the ceiling");
    // Ceiling = +z face of the inward box: polygons 9..17; the one over the centre is 13.
    Rgb above = s.radiance_at(0, 13, {1.5, 1.5, 2.5});
    const double direct = 0.7 * 10 * on_axis_factor(0.5, 0.5, 1e-3);
    EXPECT_GE(above.g, 0.95 * direct) << "direct from the light's back alone " << direct;
    EXPECT_LE(above.g, 0.7 * 10 / (1 - 0.7)) << "more than a furnace";
}

// The same at DRAFT, 5 cm under the ceiling: the patch's own link to the light's back alone
// sums past 1 (a near-field estimate over a coarse patch); the closure correction scaled it
// down with the links the patch inherits, to 0.81 of the light's direct value (4.8 for 5.9),
// where taking the excess from the inherited links first leaves it whole.
TEST(Extremes, CoarseCeilingPatchBehindALampKeepsItsDirectLight) {
    Solver s(lit_room(0.05), Settings::preset("DRAFT"));
    s.solve();
    expect_sane(s, "light 5 cm under the ceiling, DRAFT");
    Rgb above = s.radiance_at(0, 13, {1.5, 1.5, 2.5});
    const double direct = 0.7 * 10 * on_axis_factor(0.5, 0.5, 0.05);
    std::printf("[ figure ] DRAFT ceiling behind a lamp 5 cm below: %.3f of its direct light\n", above.g / direct);
    EXPECT_GE(above.g, 0.95 * direct);
    EXPECT_LE(above.g, 0.7 * 10 / (1 - 0.7)) << "more than a furnace";
}

TEST(Extremes, InterpenetratingObjects) {
    // Two boxes pushed into each other inside the lit room.
    SceneDesc sc = lit_room();
    int c1 = sc.add_cluster("A"), c2 = sc.add_cluster("B");
    scenes::add_box(sc, "A", c1, {0.8, 0.8, 0.2}, {1.6, 1.6, 1.0}, 3, Rgb::all(0.6), {});
    scenes::add_box(sc, "B", c2, {1.2, 1.1, 0.5}, {2.0, 1.9, 1.3}, 3, Rgb::all(0.6), {});
    Solver s(sc, Settings::preset("MEDIUM"));
    s.solve();
    expect_sane(s, "interpenetrating");
    // A's top outside B is lit from the ceiling light.
    EXPECT_GT(s.radiance_at(2, 1 * 9 + 0, {0.9, 0.9, 1.0}).g, 0.0);
}

TEST(Extremes, MoveInsideAnotherObjectAndFarAway) {
    auto scene = [](Vec3 cube_at) {
        SceneDesc sc = lit_room();
        int c1 = sc.add_cluster("Crate"), c2 = sc.add_cluster("Cube");
        // Lifted off the floor: a crate resting on it lets light in through the floor elements
        // under its walls (the known contact leak, README), which is not what this tests.
        scenes::add_box(sc, "Crate", c1, {0.3, 0.3, 0.05}, {1.3, 1.3, 1.05}, 2, Rgb::all(0.6), {});
        scenes::add_box(sc, "Cube", c2, cube_at, cube_at + Vec3{0.2, 0.2, 0.2}, 2, Rgb::all(0.6), {});
        return sc;
    };
    const Vec3 start{2.0, 2.0, 0.0};
    Settings st = Settings::preset("DRAFT");
    Solver s(scene(start), st);
    s.solve();
    expect_sane(s, "start");
    const auto before = s.all_corner_radiance();

    // Into the closed crate: it sees nothing lit there.
    s.move_object(3, translation(Vec3{0.7, 0.7, 0.3} - start));
    s.update();
    expect_sane(s, "inside the crate");
    double peak = 0, peak_full = 0;
    for (float v : s.corner_radiance(3)) peak = std::max(peak, double(v));
    Solver full_in(scene({0.7, 0.7, 0.3}), st);
    full_in.solve();
    for (float v : full_in.corner_radiance(3)) peak_full = std::max(peak_full, double(v));
    // Nothing lights the inside of the closed crate: the move puts the cube into the crate's
    // closed pocket (pockets.cpp), which no link from the room reaches.
    std::printf("[ figure ] cube inside a closed crate: peak %.4f after the move, %.4f in a full solve (L_ref %.4f)\n",
                peak, peak_full, s.reference_radiance());
    EXPECT_LE(peak, 1e-6 * s.reference_radiance());
    EXPECT_LE(peak_full, 1e-6 * s.reference_radiance());
    EXPECT_LE(nrmse(s.all_corner_radiance(), full_in.all_corner_radiance()), 0.03);

    // A million metres away: finite, dark, and the room as without it.
    s.move_object(3, translation({1e6, 0, 0}));
    s.update();
    expect_sane(s, "1e6 away");
    peak = 0;
    for (float v : s.corner_radiance(3)) peak = std::max(peak, double(v));
    EXPECT_LE(peak, 1e-3 * s.reference_radiance());
    SceneDesc without = scene(start);
    without.objects_mut().pop_back();
    Solver ref(without, st);
    ref.solve();
    std::vector<float> room_now;
    for (int o = 0; o < 3; ++o) {
        auto c = s.corner_radiance(o);
        room_now.insert(room_now.end(), c.begin(), c.end());
    }
    EXPECT_LE(nrmse(room_now, ref.all_corner_radiance()), 0.03);

    // And back where it started: as before.
    s.move_object(3, translation({0, 0, 0}));
    s.update();
    expect_sane(s, "back");
    EXPECT_LE(nrmse(s.all_corner_radiance(), before), 0.03);
}

// The cube inside a closed crate (separate objects, separate clusters) in a lit room. Partly
// occluded cluster links from the room into the crate's cluster used to share their flux by
// cosine among all surfaces below it, the crate's inner faces and the cube too (9 % of L_ref at
// DRAFT, 1.1 % at MEDIUM, accepted under the oracle's threshold). Now the crate's inside and
// the cube form a closed pocket (pockets.cpp) that no link from the room reaches.
TEST(Extremes, NothingLightsTheInsideOfAClosedCrate) {
    auto peak_inside = [](const char* preset) {
        SceneDesc sc = lit_room();
        int c1 = sc.add_cluster("Crate"), c2 = sc.add_cluster("Cube");
        scenes::add_box(sc, "Crate", c1, {0.3, 0.3, 0.05}, {1.3, 1.3, 1.05}, 2, Rgb::all(0.6), {});
        scenes::add_box(sc, "Cube", c2, {0.7, 0.7, 0.3}, {0.9, 0.9, 0.5}, 2, Rgb::all(0.6), {});
        Solver s(sc, Settings::preset(preset));
        s.solve();
        double peak = 0;
        for (float v : s.corner_radiance(3)) peak = std::max(peak, double(v));
        std::printf("[ figure ] cube inside a closed crate (%s): peak %.3g of L_ref\n", preset, peak / s.reference_radiance());
        return peak / s.reference_radiance();
    };
    // HIGH gives 0 as well (measured; left out here: it takes 25 s).
    for (const char* preset : {"DRAFT", "MEDIUM"}) EXPECT_LE(peak_inside(preset), 1e-6) << preset;
}

// ---------------------------------------------------------------------------------------
// Settings extremes
// ---------------------------------------------------------------------------------------

TEST(Extremes, HugeThresholdGivesTheCoarsestSolution) {
    Settings st;
    st.error_threshold = 1e9;
    SceneDesc sc = scenes::cornell_box(2);
    Solver s(sc, st);
    s.solve();
    expect_sane(s, "eps 1e9");
    // The oracle accepts every link; only links the point model cannot take (overlapping
    // bounding spheres) split, an element only where it is the larger end of such a link.
    std::printf("[ figure ] eps 1e9: element nodes %lld for %zu surfaces, links %lld\n",
                (long long)s.stats().element_nodes, s.hierarchy().surfaces.size(), (long long)s.stats().links);
    EXPECT_LE(s.stats().element_nodes, int64_t(2 * s.hierarchy().surfaces.size()));
    EXPECT_LE(s.stats().links, int64_t(20 * s.hierarchy().surfaces.size()));
    EXPECT_FALSE(s.stats().capped);
}

namespace {
// The Cornell box solved with `caps` at a threshold of 1e-9, which alone would refine without
// end: the caps stop it. Checks that the solve is sane; the test checks which cap stopped it.
Solver solve_at_tiny_threshold(Settings caps, const std::string& what) {
    caps.error_threshold = 1e-9;
    Solver s(scenes::cornell_box(2), caps);
    s.solve();
    expect_sane(s, what);
    return s;
}
}  // namespace

TEST(Extremes, TinyThresholdStopsAtTheMemoryCap) {
    // Without element or link caps, a tiny threshold refines until memory runs out; the
    // memory cap stops it first and says so (max_memory_mb; 0 = half the machine's memory).
    Settings st;
    st.max_memory_mb = 40;
    Solver s = solve_at_tiny_threshold(st, "eps 1e-9, memory cap");
    std::printf("[ figure ] eps 1e-9, max_memory_mb 40: estimate %.1f MiB, element nodes %lld, stored links %zu\n",
                s.stats().memory_bytes / 1048576.0, (long long)s.stats().element_nodes, s.links().size());
    EXPECT_TRUE(s.stats().capped);
    EXPECT_TRUE(s.stats().memory_capped);
    EXPECT_LE(s.stats().memory_bytes, int64_t(1.05 * 40 * 1048576));
    EXPECT_GE(s.stats().memory_bytes, int64_t(0.5 * 40 * 1048576));  // it did refine up to it
    EXPECT_TRUE(has_warning(s, "memory cap"));
    Settings bad;
    bad.max_memory_mb = -1;
    EXPECT_THROW(Solver(scenes::cornell_box(2), bad), std::invalid_argument);
}

TEST(Extremes, MemoryCapLeavesRoomForTheOutput) {
    // With the final gather on, refinement stops at max_memory_mb with room for the output's
    // trace (memory.cpp forecasts it): what the bake holds at the end, trace included, stays
    // near the cap, where it once stopped the links at the cap and added the trace on top.
    Settings st = Settings::preset("MEDIUM");
    Solver free_run(scenes::cornell_box(4), st);
    free_run.solve();
    const Stats& f = free_run.stats();
    ASSERT_GT(f.gather_bytes, 0);
    // The forecast made before the gather is of the trace's order (it counts every link
    // reaching a point; shared points keep fewer).
    EXPECT_GE(double(f.gather_forecast_bytes), 0.5 * double(f.gather_bytes));
    EXPECT_LE(double(f.gather_forecast_bytes), 3.0 * double(f.gather_bytes));
    // A cap at 60 % of what the free run held.
    st.max_memory_mb = 0.6 * double(f.memory_bytes) / 1048576.0;
    Solver capped(scenes::cornell_box(4), st);
    capped.solve();
    expect_sane(capped, "memory cap with output");
    const Stats& c = capped.stats();
    std::printf("[ figure ] MEDIUM Cornell box: free %.1f MiB (trace %.1f, forecast %.1f); cap %.1f MiB: held %.1f MiB\n",
                f.memory_bytes / 1048576.0, f.gather_bytes / 1048576.0, f.gather_forecast_bytes / 1048576.0,
                st.max_memory_mb, c.memory_bytes / 1048576.0);
    EXPECT_TRUE(c.memory_capped);
    EXPECT_GT(c.gather_bytes, 0);
    EXPECT_LE(double(c.memory_bytes), 1.1 * st.max_memory_mb * 1048576.0);
}

namespace {
// This process's resident bytes now (Linux), after the heap's free memory is handed back.
double resident_bytes() {
    malloc_trim(0);
    std::ifstream statm("/proc/self/statm");
    long total = 0, resident = 0;
    statm >> total >> resident;
    return double(resident) * double(sysconf(_SC_PAGESIZE));
}
}  // namespace

TEST(Extremes, MemoryEstimateCoversWhatTheBakeHolds) {
    // max_memory_mb is held against MemoryBudget::estimate: an estimate that left out a large
    // part of what a bake holds (the gather plan, the scene's and hierarchy's tables) would let
    // the process grow past the cap. What the process holds after a MEDIUM bake beyond what it
    // held before, freed memory handed back, is within the estimate; and the estimate is not
    // far above it, or a cap would stop bakes for nothing.
#if defined(__SANITIZE_ADDRESS__)
    GTEST_SKIP() << "ASan's allocator keeps what is freed";
#endif
    // Two threads on any machine, and a first bake of the same scene before the one measured:
    // the thread pools and each thread's scratch buffers, which outlive a solver, are then
    // already there.
    Settings st = Settings::preset("MEDIUM");
    st.threads = 2;
    {
        Solver warm(scenes::box_room(12), st);
        warm.solve();
    }
    const double before = resident_bytes();
    Solver s(scenes::box_room(12), st);
    s.solve();
    const double grown = resident_bytes() - before;
    const double estimate = double(s.stats().memory_bytes);
    std::printf("[ figure ] MEDIUM box room (12): estimate %.1f MiB, resident growth %.1f MiB\n", estimate / 1048576.0,
                grown / 1048576.0);
    EXPECT_GE(estimate, 0.9 * grown);
    EXPECT_LE(estimate, 1.6 * grown);
}

TEST(Extremes, TinyThresholdStopsAtTheElementCap) {
    // The caps that exist (settings.h): max_elements and max_links, reported by
    // Stats::capped and a warning saying so. There is no memory cap as such.
    Settings st;
    st.max_elements = 4000;
    st.max_links = 200000;  // with the element cap alone, links grow to the 10M default (~4 GB)
    Solver s = solve_at_tiny_threshold(st, "eps 1e-9, element cap");
    std::printf("[ figure ] eps 1e-9, max_elements 4000: element nodes %lld, stored links %zu, capped %d, warnings %zu\n",
                (long long)s.stats().element_nodes, s.links().size(), int(s.stats().capped), s.stats().warnings.size());
    EXPECT_TRUE(s.stats().capped);
    EXPECT_TRUE(has_warning(s, "cap")) << "a capped solve must say so in its warnings";
    // Judgements of one wave are made in parallel against the count before the wave; apply()
    // re-checks the cap (was 5,662 element nodes for 4,000), exact in the test below.
    EXPECT_LE(s.stats().element_nodes, 2 * st.max_elements);
}

// Was 5,662 element nodes for max_elements = 4,000: apply() now re-checks both caps.
TEST(Extremes, ElementCapIsExact) {
    Settings st;
    st.error_threshold = 1e-9;
    st.max_elements = 4000;
    st.max_links = 200000;
    Solver s(scenes::cornell_box(2), st);
    s.solve();
    EXPECT_LE(s.stats().element_nodes, st.max_elements);
}

TEST(Extremes, TinyThresholdStopsAtTheLinkCap) {
    Settings st;
    st.max_links = 20000;
    Solver s = solve_at_tiny_threshold(st, "eps 1e-9, link cap");
    const int64_t stored = int64_t(s.links().size());
    std::printf("[ figure ] eps 1e-9 with max_links 20000: stored links %lld (active %lld), capped %d\n",
                (long long)stored, (long long)s.stats().links, int(s.stats().capped));
    EXPECT_TRUE(s.stats().capped);
    // apply() counts the links the wave has queued: at most one refinement past the cap.
    EXPECT_LE(stored, st.max_links + 4);
}

TEST(Extremes, ZeroMinimumElementArea) {
    // Refinement is then bounded by the threshold and the caps only.
    Settings st = Settings::preset("DRAFT");
    st.min_area_fraction = 0;
    st.max_elements = 200000;
    Solver s(lit_room(), st);
    s.solve();
    expect_sane(s, "min area 0");
    std::printf("[ figure ] min area 0 (DRAFT): element nodes %lld, links %lld, capped %d\n",
                (long long)s.stats().element_nodes, (long long)s.stats().links, int(s.stats().capped));
    EXPECT_FALSE(s.stats().capped) << "the threshold alone should stop refinement";
    Solver d(lit_room(), Settings::preset("DRAFT"));
    d.solve();
    EXPECT_LE(nrmse(s.all_corner_radiance(), d.all_corner_radiance()), 0.1);
}

// ---------------------------------------------------------------------------------------
// Bad input: a clear InputError naming the object, never a crash
// ---------------------------------------------------------------------------------------

TEST(Extremes, NonFiniteInputIsRejectedNamingTheObject) {
    const double nan = std::nan(""), inf = std::numeric_limits<double>::infinity();
    auto tri = [](Vec3 a, Rgb rho, Rgb e) {
        return make_object("Bad", -1, {{0, 0, 0}, {1, 0, 0}, a}, {{0, 1, 2}}, rho, e);
    };
    for (double bad : {nan, inf, -inf}) {
        SceneDesc sc;
        auto expect_error = [&](ObjectDesc o, const char* what) {
            try {
                sc.add_object(std::move(o));
                ADD_FAILURE() << what << " " << bad << " accepted";
            } catch (const InputError& e) {
                EXPECT_NE(std::string(e.what()).find("Bad"), std::string::npos) << e.what();
            }
        };
        expect_error(tri({0, bad, 0}, Rgb::all(0.5), {}), "vertex");
        expect_error(tri({0, 1, 0}, Rgb{0.5, bad, 0.5}, {}), "reflectance");
        expect_error(tri({0, 1, 0}, Rgb::all(0.5), Rgb{bad, 1, 1}), "emission");
        EXPECT_EQ(sc.objects().size(), 0u);
    }
    // Negative emission.
    SceneDesc sc;
    EXPECT_THROW(sc.add_object(tri({0, 1, 0}, Rgb::all(0.5), Rgb{1, -1e-12, 1})), InputError);
    EXPECT_THROW(sc.add_object(tri({0, 1, 0}, Rgb{-0.1, 0.5, 0.5}, {})), InputError);

    // Through the dynamic API, after a solve: rejected, and the kept solution untouched.
    Solver s(lit_room(), Settings::preset("DRAFT"));
    s.solve();
    const auto before = s.all_corner_radiance();
    for (double bad : {nan, inf, -inf}) {
        EXPECT_THROW(s.set_emission(1, {Rgb{1, bad, 1}}), InputError);
        for (int i = 0; i < 16; ++i) {
            auto m = translation({0.1, 0, 0});
            m[i] = bad;
            EXPECT_THROW(s.move_object(0, m), InputError) << "matrix entry " << i;
        }
    }
    EXPECT_THROW(s.set_emission(1, {Rgb{1, -1, 1}}), InputError);
    EXPECT_THROW(s.set_emission(1, {Rgb::all(1), Rgb::all(1)}), InputError);  // wrong count
    s.update();  // nothing pending: a no-op
    EXPECT_EQ(s.all_corner_radiance(), before);
}

TEST(Extremes, NonFiniteSettingsAreRejected) {
    const double nan = std::nan(""), inf = std::numeric_limits<double>::infinity();
    for (double bad : {nan, inf, -1.0, 0.0}) {
        Settings st;
        st.error_threshold = bad;
        EXPECT_THROW(Solver(SceneDesc{}, st), std::invalid_argument) << bad;
        st = Settings{};
        st.tolerance = bad;
        EXPECT_THROW(Solver(SceneDesc{}, st), std::invalid_argument) << bad;
    }
    Settings st;
    st.min_area_fraction = nan;
    EXPECT_THROW(Solver(SceneDesc{}, st), std::invalid_argument);
}

TEST(Extremes, EmptySceneSolvesToNothing) {
    Solver s(SceneDesc{}, Settings::preset("MEDIUM"));
    s.solve();
    EXPECT_TRUE(s.solved());
    EXPECT_TRUE(s.stats().no_emitters);
    EXPECT_EQ(s.stats().primitives, 0);
    EXPECT_THROW(s.corner_radiance(0), std::out_of_range);
    EXPECT_THROW(s.move_object(0, translation({1, 0, 0})), InputError);
    s.update();
    EXPECT_TRUE(s.solved());
}

TEST(Extremes, ObjectsWithoutPolygons) {
    // A modifier that produces nothing, and loose vertices only: empty output, no effect.
    SceneDesc sc = lit_room();
    ObjectDesc empty;
    empty.name = "Empty";
    sc.add_object(empty);
    ObjectDesc verts;
    verts.name = "Points";
    verts.vertices = {{100, 100, 100}, {-1e12, 0, 0}};  // far away: they must not widen the scene
    sc.add_object(verts);
    int cl = sc.add_cluster("Nothing");
    ObjectDesc in_cluster;
    in_cluster.name = "Nothing";
    in_cluster.cluster = cl;
    sc.add_object(in_cluster);
    Solver s(sc, Settings::preset("DRAFT"));
    s.solve();
    expect_sane(s, "empty objects");
    EXPECT_TRUE(s.corner_radiance(2).empty());
    EXPECT_TRUE(s.corner_radiance(3).empty());
    Solver ref(lit_room(), Settings::preset("DRAFT"));
    ref.solve();
    std::vector<float> room;
    for (int o = 0; o < 2; ++o) {
        auto c = s.corner_radiance(o);
        room.insert(room.end(), c.begin(), c.end());
    }
    // Loose vertices used to set the internal frame: 1e6 away the room came out 7x too dark,
    // 1e12 away every polygon snapped to zero area and was skipped.
    EXPECT_EQ(s.stats().skipped_polygons, 0);
    EXPECT_LE(nrmse(room, ref.all_corner_radiance()), 1e-6) << "loose vertices changed the solution";
    // Moving them is harmless.
    s.move_object(2, translation({1, 2, 3}));
    s.move_object(4, translation({1, 2, 3}));
    s.update();
    expect_sane(s, "moved empty objects");
}

namespace {
// The fan pieces of a big n-gon are slivers from one apex across the whole polygon, each one
// element (below the minimum area): pointwise values are sliver averages (the disc's centre
// reads 0.23 for an exact 0.37), but each piece gets its own light right, so the reflected
// power of the whole polygon must be right: compared with a midpoint-rule integral of the
// exact point form factor over the polygon's own pieces.
void expect_disc_power(const Solver& s, const std::vector<Vec3>& rim, const std::string& what) {
    const Poly light = quad({-0.25, -0.25, 1}, {-0.25, 0.25, 1}, {0.25, 0.25, 1}, {0.25, -0.25, 1});
    const Hierarchy& h = s.hierarchy();
    double got = 0, area = 0;
    for (const Node* n : front_leaves(s, 0)) {
        got += n->L.g * n->area;
        area += n->area;
    }
    got /= area;
    // Exact: grid over the bounding square, points inside the polygon (even-odd rule).
    const int m = 200;
    double sum = 0;
    int inside = 0;
    for (int i = 0; i < m; ++i)
        for (int j = 0; j < m; ++j) {
            Vec3 p{-1 + (i + 0.5) * 2.0 / m, -1 + (j + 0.5) * 2.0 / m, 0};
            bool in = false;
            for (size_t a = 0, b = rim.size() - 1; a < rim.size(); b = a++)
                if ((rim[a].y > p.y) != (rim[b].y > p.y) &&
                    p.x < (rim[b].x - rim[a].x) * (p.y - rim[a].y) / (rim[b].y - rim[a].y) + rim[a].x)
                    in = !in;
            if (!in) continue;
            sum += 0.5 * 10 * point_polygon_form_factor(p, {0, 0, 1}, light, light.normal());
            ++inside;
        }
    const double exact = sum / inside;
    std::printf("[ figure ] %s: mean radiance %.4f vs exact %.4f; centre %.4f (%zu pieces)\n", what.c_str(), got, exact,
                s.radiance_at(0, 0, {0.01, 0, 0}).g, h.prims.size() - 1);
    EXPECT_NEAR(got, exact, 0.05 * exact) << what;
}
// A unit disc of n corners (one polygon) as vertices and corner list.
void unit_disc(int n, std::vector<Vec3>& v, std::vector<int>& f) {
    v.resize(n);
    f.resize(n);
    for (int i = 0; i < n; ++i) {
        double a = 2 * kPi * i / n;
        v[i] = {std::cos(a), std::sin(a), 0};
        f[i] = i;
    }
}

// The disc as one object, a small light above it, solved at DRAFT.
Solver solve_disc_under_light(const char* name, const std::vector<Vec3>& v, const std::vector<int>& f) {
    SceneDesc sc;
    sc.add_object(make_object(name, -1, v, {f}, Rgb::all(0.5), {}));
    scenes::add_grid(sc, "light", -1, {Vec3{-0.25, -0.25, 1}, Vec3{-0.25, 0.25, 1}, Vec3{0.25, 0.25, 1}, Vec3{0.25, -0.25, 1}},
                     1, 1, {}, Rgb::all(10.0), false);
    Solver s(sc, Settings::preset("DRAFT"));
    s.solve();
    return s;
}

// The unit disc of kDiscCorners corners, with corner `moved` put at `to` (none moved when
// `moved` < 0), solved under the light; checks that the solve is sane and that the disc
// reflects the light's power, and returns the solver for the test's own checks.
constexpr int kDiscCorners = 100000;
Solver solve_unit_disc(const char* name, const std::string& what, int moved = -1, Vec3 to = {}) {
    std::vector<Vec3> v;
    std::vector<int> f;
    unit_disc(kDiscCorners, v, f);
    if (moved >= 0) v[moved] = to;
    Solver s = solve_disc_under_light(name, v, f);
    expect_sane(s, what);
    expect_disc_power(s, v, what);
    return s;
}

// Pieces of object 0 whose normal points down (a fan from a bad apex flips some).
int flipped_pieces(const Solver& s) {
    const Hierarchy& h = s.hierarchy();
    int flipped = 0;
    for (const Primitive& p : h.prims)
        if (p.object == 0 && h.nodes[h.surfaces[p.front].root].normal.z < 0) ++flipped;
    return flipped;
}
}  // namespace

TEST(Extremes, HundredThousandVertexConvexNgon) {
    // scene.h takes Blender's polygon layout, so n-gons are accepted and fan-split natively.
    Solver s = solve_unit_disc("disc", "convex 100k-gon");
    EXPECT_EQ(s.stats().primitives, kDiscCorners - 2 + 1);
}

TEST(Extremes, HundredThousandVertexConcaveNgon) {
    // The same disc with one vertex pulled to the centre (a reflex corner half-way round):
    // the fan apex search must still finish and the pieces must face the right way.
    Solver s = solve_unit_disc("pacman", "concave 100k-gon", kDiscCorners / 2, {-0.5, 0, 0});
    // Every piece faces +z like the polygon (a fan from a bad apex would flip some).
    EXPECT_EQ(flipped_pieces(s), 0);
}

TEST(Extremes, HundredThousandVertexNgonNotchedBeforeItsFirstCorner) {
    // Found through the add-on's 100k n-gon case: the reflex corner is the LAST one, so
    // every apex before it fails only at the end of its fan and testing all of them was O(n^2)
    // (20k corners: 20 s, 100k: minutes). The apex search has an O(n) budget, then tries the
    // reflex corners. (No timed assertion: a regression shows as this test running for minutes.)
    Solver s = solve_unit_disc("notched", "notched 100k-gon", kDiscCorners - 1, {0.9, 0, 0});
    EXPECT_EQ(s.stats().primitives, kDiscCorners - 2 + 1);
    EXPECT_EQ(flipped_pieces(s), 0);      // fanned from the notch: every piece faces +z
}

TEST(Extremes, UShapedNgonWithoutAFanApexIsClippedIntoEars) {
    // A U-shaped floor drawn as one n-gon: no corner sees the whole polygon, so no fan stays
    // positive; it is triangulated by ear clipping (a fan from corner 0 flipped pieces).
    std::vector<Vec3> v = {{0, 0, 0}, {3, 0, 0}, {3, 3, 0}, {2, 3, 0}, {2, 1, 0}, {1.5, 1, 0}, {1, 1, 0}, {1, 3, 0}, {0, 3, 0}};
    std::vector<int> f(v.size());
    for (size_t i = 0; i < v.size(); ++i) f[i] = int(i);
    Solver s = solve_disc_under_light("U", v, f);
    expect_sane(s, "U-shaped n-gon");
    EXPECT_EQ(flipped_pieces(s), 0);
    double area = 0;
    for (const Primitive& p : s.hierarchy().prims)
        if (p.object == 0) area += p.poly.area();
    const double unit = s.hierarchy().unit;
    EXPECT_NEAR(area * unit * unit, 7.0, 1e-9);  // 3 x 3 minus the 1 x 2 notch
    EXPECT_FALSE(has_warning(s, "concave"));
}

TEST(Extremes, RadianceAtFarOrNonFinitePoints) {
    // Found by the fuzzer: a query point so far away that every distance overflowed to inf
    // walked to child -1 (out-of-bounds read). Far points now end at a leaf; NaN is an error.
    Solver s(lit_room(), Settings::preset("DRAFT"));
    s.solve();
    for (size_t o = 0; o < s.scene().objects().size(); ++o) {
        if (s.scene().objects()[o].polygon_count() == 0) continue;
        for (double far : {1e300, -1e300, 1e30}) {
            Rgb r = s.radiance_at(int(o), 0, Vec3{far, -far, far});
            EXPECT_TRUE(finite(r)) << "object " << o << " at " << far;
        }
        EXPECT_THROW(s.radiance_at(int(o), 0, Vec3{std::nan(""), 0, 0}), InputError);
    }
}

// Fuzzer finding (this session's fuzz run, after objects added/removed joined the target; the
// same on the code before it): a self-overlapping 8-corner polygon (corners 1 0 2 3 0 2 0 2,
// fanned into coincident triangles facing each other) with reflectance 0.999 next to a 1e6
// emitter. Its couplings sum above 1 where the closure correction does not apply, so the
// gathering diverges: the first solve ends at 5e22 (finite, wrong), the update after a rigid
// move overflows to inf. A fresh solve of the moved scene converges (max 1e6). Fixed by the
// guard in set_closure (gathering.cpp): no leaf's couplings sum above 1.
TEST(Extremes, SelfOverlappingPolygonNearOneDoesNotDiverge) {
    SceneDesc s;
    ObjectDesc a;
    a.name = "obj0";
    a.vertices = {{-0.0045, -0.0065, -0.002}, {-0.004, -0.0075, -0.00275}, {-0.00225, -0.00375, -0.00575},
                  {-0.00325, -0.004, -0.00275}};
    a.loop_starts = {0};
    a.loop_totals = {4};
    a.corner_verts = {0, 1, 2, 3};
    a.reflectance = {{0, 0, 0}};
    a.emission = {{0, 0, 0}};
    s.add_object(a);
    ObjectDesc b;
    b.name = "obj1";
    b.vertices = {{-0.5, 0, 1.5}, {0.5, 0, 1.5}, {-0.5, 0, -2.75}, {-3.25, -4, -2.75}};
    b.loop_starts = {0, 4};
    b.loop_totals = {4, 8};
    b.corner_verts = {1, 3, 0, 2, 1, 0, 2, 3, 0, 2, 0, 2};
    b.reflectance = {{0, 0.3, 0}, {0.999, 0.999, 0.999}};
    b.emission = {{1e6, 0, 0}, {0, 0, 0}};
    s.add_object(b);
    Settings st;
    st.error_threshold = 0.2;
    st.min_area_fraction = 0.001;
    st.max_elements = 700;
    st.max_links = 7500;
    st.progressive_refinement = false;
    st.rays_per_link = 2;
    st.max_iterations = 122;
    st.max_refine_rounds = 2;
    st.closure_rays = 8;
    st.seed = 111;
    st.threads = 1;
    Solver solver(s, st);
    solver.solve();
    for (float v : solver.all_corner_radiance()) EXPECT_LE(v, 1e7f);  // no light beyond what E/(1-rho) allows
    const std::array<double, 16> m = {-0.96592582628906842, 0, -0.25881904510252035, 1.25, 0, 1, 0, 1.25,
                          0.25881904510252035,  0, -0.96592582628906842, 1.25, 0, 0, 0, 1};
    solver.move_object(1, m);
    solver.update();
    for (float v : solver.all_corner_radiance()) ASSERT_TRUE(std::isfinite(v));
}

// ---------------------------------------------------------------------------------------
// Warped quads and turned moves (meshes from Bevel and Subdivision Surface)
// ---------------------------------------------------------------------------------------

namespace {

// A rigid move: a turn by `angle` about the axis through `centre` along coordinate `axis`,
// then a translation by t (row-major 4 x 4, as Solver::move_object takes it).
std::array<double, 16> turn_about(int axis, double angle, Vec3 centre, Vec3 t) {
    double R[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    const int i = (axis + 1) % 3, j = (axis + 2) % 3;
    const double c = std::cos(angle), s = std::sin(angle);
    R[i * 3 + i] = c, R[i * 3 + j] = -s, R[j * 3 + i] = s, R[j * 3 + j] = c;
    // p' = R (p - centre) + centre + t
    Vec3 off;
    for (int r = 0; r < 3; ++r) off[r] = centre[r] + t[r] - (R[r * 3] * centre.x + R[r * 3 + 1] * centre.y + R[r * 3 + 2] * centre.z);
    return {R[0], R[1], R[2], off.x, R[3], R[4], R[5], off.y, R[6], R[7], R[8], off.z, 0, 0, 0, 1};
}

// Object o of `sc` placed by the row-major matrix m (a full solve's scene after a move).
void place(SceneDesc& sc, int o, const std::array<double, 16>& m) {
    for (Vec3& v : sc.objects_mut()[size_t(o)].vertices)
        v = Vec3{m[0] * v.x + m[1] * v.y + m[2] * v.z + m[3], m[4] * v.x + m[5] * v.y + m[6] * v.z + m[7],
                 m[8] * v.x + m[9] * v.y + m[10] * v.z + m[11]};
}

// An n x n grid over [x0, x1] x [y0, y1] at height z whose vertices are lifted by +-warp in a
// checkerboard: every quad is warped (planar only to warp / cell), crossing its neighbours'
// tangent planes four times, as the quads of a bevelled, subdivided cushion do.
ObjectDesc warped_grid(const std::string& name, int cluster, double x0, double x1, double y0, double y1, double z,
                       int n, double warp, Rgb rho) {
    ObjectDesc o;
    o.name = name;
    o.cluster = cluster;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i)
            o.vertices.push_back({x0 + (x1 - x0) * i / n, y0 + (y1 - y0) * j / n, z + (((i + j) & 1) ? warp : -warp)});
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            o.loop_starts.push_back(int32_t(o.corner_verts.size()));
            o.loop_totals.push_back(4);
            const int a = j * (n + 1) + i;
            o.corner_verts.insert(o.corner_verts.end(), {a, a + 1, a + n + 2, a + n + 1});
            o.reflectance.push_back(rho);
            o.emission.push_back({});
            o.two_sided.push_back(1);
        }
    return o;
}

}  // namespace

TEST(Extremes, WarpedQuadsBakeAsTheirFlatTwinAndSurviveTurnedMoves) {
    // A rug of warped quads in the lit room with a crate on it: the solve, and the crate moved
    // and turned 0.6 rad into a wall, must stay sane; the rug must light as a flat one does.
    auto scene = [](double warp) {
        SceneDesc sc = lit_room(0.1, 4);
        sc.add_object(warped_grid("rug", -1, 0.5, 2.5, 0.5, 2.5, 0.01, 16, warp, Rgb::all(0.6)));
        const int c = sc.add_cluster("Crate");
        scenes::add_box(sc, "crate", c, {1.0, 1.0, 0.02}, {1.6, 1.5, 0.6}, 3, Rgb::all(0.5), {});
        return sc;
    };
    const double cell = 2.0 / 16;
    const Settings st = Settings::preset("DRAFT");
    Solver warped(scene(2e-5 * cell), st), flat(scene(0.0), st);
    warped.solve();
    flat.solve();
    expect_sane(warped, "warped rug");
    ASSERT_EQ(warped.hierarchy().prims.size(), flat.hierarchy().prims.size()) << "the warped quads stay quads";
    auto mean = [](const std::vector<float>& c) {
        double s = 0;
        for (float v : c) s += v;
        return s / double(c.size());
    };
    const double mw = mean(warped.corner_radiance(2)), mf = mean(flat.corner_radiance(2));
    EXPECT_NEAR(mw, mf, 0.02 * mf) << "rug mean, warped " << mw << " flat " << mf;

    // Into the wall at x = 3, turned.
    const auto m = turn_about(2, 0.6, {1.3, 1.25, 0.3}, {1.5, 0.3, 0});
    warped.move_object(3, m);
    warped.update();
    expect_sane(warped, "crate turned into the wall");
    SceneDesc moved = scene(2e-5 * cell);
    place(moved, 3, m);
    Solver full(moved, st);
    full.solve();
    expect_sane(full, "full solve with the crate in the wall");
    EXPECT_LE(nrmse(warped.all_corner_radiance(), full.all_corner_radiance()), 0.03);
}

TEST(Extremes, CornellBlockMovedAndTurned) {
    // The short block moved across the floor and turned 0.4 rad, then turned 0.6 rad into the
    // red wall: the update stays sane and equals a full solve of the moved scene.
    const int block = 6;
    const Settings st = Settings::preset("DRAFT");
    Solver s(scenes::cornell_box(4), st);
    s.solve();
    const Vec3 centre{0.186, 0.0825, 0.169};
    for (const auto& m : {turn_about(1, 0.4, centre, {0.09, 0, 0.12}), turn_about(1, 0.6, centre, {0.33, 0, 0.05})}) {
        s.move_object(block, m);
        s.update();
        expect_sane(s, "moved block");
        SceneDesc moved = scenes::cornell_box(4);
        place(moved, block, m);
        Solver full(moved, st);
        full.solve();
        EXPECT_LE(nrmse(s.all_corner_radiance(), full.all_corner_radiance()), 0.03);
    }
}
