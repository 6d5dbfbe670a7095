// Form factors against closed forms (NOTES.md, Howell's catalogue): the analytic kernel
// itself, and the hierarchical solver's transport, which is what users get.
#include <gtest/gtest.h>

#include "radiosity/random.h"
#include "radiosity/transfer.h"
#include "test_util.h"

using namespace radiosity;
using namespace radiosity::testing;

namespace {

// Parallel directly opposed a x b rectangles at distance c (C-11).
double parallel_rects(double a, double b, double c) {
    double X = a / c, Y = b / c;
    double t1 = std::log(std::sqrt((1 + X * X) * (1 + Y * Y) / (1 + X * X + Y * Y)));
    double t2 = X * std::sqrt(1 + Y * Y) * std::atan(X / std::sqrt(1 + Y * Y));
    double t3 = Y * std::sqrt(1 + X * X) * std::atan(Y / std::sqrt(1 + X * X));
    return 2 / (kPi * X * Y) * (t1 + t2 + t3 - X * std::atan(X) - Y * std::atan(Y));
}

// Receiver a x b at z=0 facing +z; sender a x b at z=c facing -z.
std::pair<Poly, Poly> parallel_pair(double a, double b, double c) {
    Poly r = quad({0, 0, 0}, {a, 0, 0}, {a, b, 0}, {0, b, 0});
    Poly s = quad({0, 0, c}, {0, b, c}, {a, b, c}, {a, 0, c});
    return {r, s};
}

// Plate w (in the xy plane, along +y) and plate h (xz plane, along +z) sharing the x edge of length l.
std::pair<Poly, Poly> perpendicular_pair(double l, double w, double h) {
    Poly pw = quad({0, 0, 0}, {l, 0, 0}, {l, w, 0}, {0, w, 0});     // normal +z
    Poly ph = quad({0, 0, 0}, {0, 0, h}, {l, 0, h}, {l, 0, 0});     // normal +y
    return {pw, ph};
}

// A regular polygon disc as a triangle fan (the kernel is additive over the fan).
std::vector<Poly> disc(Vec3 c, double r, bool up, int n = 512) {
    std::vector<Poly> out;
    for (int i = 0; i < n; ++i) {
        double a0 = 2 * kPi * i / n, a1 = 2 * kPi * (i + 1) / n;
        Poly t;
        t.n = 3;
        Vec3 p0 = c + Vec3{r * std::cos(a0), r * std::sin(a0), 0}, p1 = c + Vec3{r * std::cos(a1), r * std::sin(a1), 0};
        t.v = up ? std::array<Vec3, 4>{c, p0, p1, Vec3{}} : std::array<Vec3, 4>{c, p1, p0, Vec3{}};
        out.push_back(t);
    }
    return out;
}

}  // namespace

TEST(AnalyticKernel, ParallelRectanglesMatchHowell) {
    EXPECT_NEAR(parallel_rects(1, 1, 1), 0.199825, 1e-6);
    const double cases[][4] = {{1, 1, 1, 0.199825}, {1, 1.5, 0.5, 0.475576}, {2, 2, 1, 0.415253}};
    for (auto& c : cases) {
        auto [r, s] = parallel_pair(c[0], c[1], c[2]);
        EXPECT_NEAR(form_factor(r, s), c[3], 0.005 * c[3]) << c[0] << "x" << c[1] << " at " << c[2];
    }
}

TEST(AnalyticKernel, PerpendicularRectanglesMatchHowell) {
    const double cases[][3] = {{1, 1, 0.200044}, {2, 1, 0.116426}, {1, 2, 0.232853}};  // w, h, F(w->h)
    for (auto& c : cases) {
        auto [pw, ph] = perpendicular_pair(1, c[0], c[1]);
        EXPECT_NEAR(form_factor(pw, ph), c[2], 0.005 * c[2]) << "w=" << c[0] << " h=" << c[1];
    }
}

TEST(AnalyticKernel, CoaxialDiscsMatchHowell) {
    auto check = [](double r1, double r2, double L, double expect) {
        // F from disc 1 (receiver, at z=0 facing up) to disc 2 (at z=L facing down).
        auto d1 = disc({0, 0, 0}, r1, true), d2 = disc({0, 0, L}, r2, false);
        double num = 0, area = 0;
        for (const Poly& r : d1) {
            double f = 0;
            for (const Poly& s : d2) f += form_factor(r, s, 1);
            num += r.area() * f;
            area += r.area();
        }
        EXPECT_NEAR(num / area, expect, 0.005 * expect) << r1 << " " << r2 << " " << L;
    };
    check(1, 1, 1, 0.381966);
    check(0.1, 0.2, 0.5, 0.133931);
}

TEST(AnalyticKernel, ReciprocityOnRandomPolygons) {
    Rng rng(42);
    auto rnd = [&](double a, double b) { return a + (b - a) * rng.next(); };
    int checked = 0;
    for (int t = 0; t < 40 && checked < 15; ++t) {
        Poly a, b;
        a.n = 3;
        b.n = 4;
        Vec3 c1{rnd(-1, 1), rnd(-1, 1), rnd(-1, 1)}, c2{rnd(-1, 1), rnd(-1, 1), rnd(2, 3)};
        a.v = {c1, c1 + Vec3{rnd(0.3, 1), rnd(-0.2, 0.2), rnd(-0.2, 0.2)}, c1 + Vec3{rnd(-0.2, 0.2), rnd(0.3, 1), rnd(-0.2, 0.2)}, Vec3{}};
        double sx = rnd(0.3, 1), sy = rnd(0.3, 1);
        b.v = {c2, c2 + Vec3{0, sy, 0}, c2 + Vec3{sx, sy, 0}, c2 + Vec3{sx, 0, 0}};  // facing -z
        double fab = form_factor(a, b, 5), fba = form_factor(b, a, 5);
        if (fab < 1e-3 || fba < 1e-3) continue;
        EXPECT_NEAR(a.area() * fab, b.area() * fba, 0.01 * a.area() * fab);
        ++checked;
    }
    EXPECT_GE(checked, 10);
}

// --- Through the hierarchical solver: an emitter of radiance 1 (black) and a receiver of
// reflectance rho; the receiver's mean radiance is rho * F(receiver -> emitter).

namespace {
double solved_form_factor(const Poly& rcv, const Poly& src, const Settings& st, int grid = 1) {
    SceneDesc s;
    scenes::add_grid(s, "receiver", -1, {rcv.v[0], rcv.v[1], rcv.v[2], rcv.v[3]}, grid, grid, Rgb::all(0.5), {}, false);
    scenes::add_grid(s, "emitter", -1, {src.v[0], src.v[1], src.v[2], src.v[3]}, grid, grid, {}, Rgb::all(1.0), false);
    Solver solver(s, st);
    solver.solve();
    return object_front_radiance(solver, 0).r / 0.5;
}
}  // namespace

TEST(SolverTransport, ParallelAndPerpendicularPlatesAtHigh) {
    Settings st = Settings::preset("HIGH");
    st.closure_rays = 0;  // open scene anyway; measure the raw transport
    {
        auto [r, s] = parallel_pair(1, 1, 1);
        EXPECT_NEAR(solved_form_factor(r, s, st), 0.199825, 0.005 * 0.199825);
    }
    {
        auto [r, s] = parallel_pair(2, 2, 1);
        EXPECT_NEAR(solved_form_factor(r, s, st), 0.415253, 0.005 * 0.415253);
    }
    const double cases[][3] = {{1, 1, 0.200044}, {2, 1, 0.116426}, {1, 2, 0.232853}};
    for (auto& c : cases) {
        auto [pw, ph] = perpendicular_pair(1, c[0], c[1]);
        EXPECT_NEAR(solved_form_factor(pw, ph, st), c[2], 0.005 * c[2]) << "w=" << c[0] << " h=" << c[1];
    }
}

TEST(SolverTransport, ReciprocityOfSolvedTransport) {
    Settings st = Settings::preset("HIGH");
    st.closure_rays = 0;
    Rng rng(7);
    for (int t = 0; t < 5; ++t) {
        double w = 0.5 + rng.next(), d = 0.5 + rng.next(), off = rng.next() - 0.5;
        Poly a = quad({0, 0, 0}, {w, 0, 0}, {w, w, 0}, {0, w, 0});
        Poly b = quad({off, 0, d}, {off, 1, d}, {off + 1.2, 1, d}, {off + 1.2, 0, d});
        double fab = solved_form_factor(a, b, st), fba = solved_form_factor(b, a, st);
        EXPECT_NEAR(a.area() * fab, b.area() * fba, 0.01 * a.area() * fab) << "pair " << t;
    }
}

TEST(SolverTransport, UnitCubeClosureWithoutCorrection) {
    // Floor of a unit cube room receives from the other five walls (radiance 1):
    // opposite + 4 adjacent = 1. The closure correction is off, so this measures the
    // form factors themselves.
    SceneDesc s;
    const Vec3 P[8] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
    scenes::add_grid(s, "floor", -1, {P[0], P[1], P[2], P[3]}, 1, 1, Rgb::all(0.5), {}, false);
    const int walls[5][4] = {{4, 7, 6, 5}, {0, 4, 5, 1}, {1, 5, 6, 2}, {2, 6, 7, 3}, {3, 7, 4, 0}};
    for (auto& w : walls)
        scenes::add_grid(s, "wall", -1, {P[w[0]], P[w[1]], P[w[2]], P[w[3]]}, 1, 1, {}, Rgb::all(1.0), false);
    Settings st = Settings::preset("HIGH");
    st.closure_rays = 0;
    Solver solver(s, st);
    solver.solve();
    EXPECT_NEAR(object_front_radiance(solver, 0).r / 0.5, 1.0, 0.005);
}

TEST(SolverTransport, BlockerLeavesTheUnblockedPart) {
    // A small receiver under a 1x1 emitter at height 1; an opaque black plate halfway
    // covers x < 0.5 (the half-plane whose edge lies over the receiver's centre), so the
    // receiver sees the emitter's x > 0.5 half only.
    const double r0 = 0.475, r1 = 0.525;
    Poly rcv = quad({r0, r0, 0}, {r1, r0, 0}, {r1, r1, 0}, {r0, r1, 0});
    Poly em = quad({0, 0, 1}, {0, 1, 1}, {1, 1, 1}, {1, 0, 1});
    Poly half = quad({0.5, 0, 1}, {0.5, 1, 1}, {1, 1, 1}, {1, 0, 1});
    SceneDesc s;
    scenes::add_grid(s, "receiver", -1, {rcv.v[0], rcv.v[1], rcv.v[2], rcv.v[3]}, 1, 1, Rgb::all(0.5), {}, false);
    scenes::add_grid(s, "emitter", -1, {em.v[0], em.v[1], em.v[2], em.v[3]}, 1, 1, {}, Rgb::all(1.0), false);
    scenes::add_grid(s, "blocker", -1, {Vec3{-3, -3, 0.5}, Vec3{0.5, -3, 0.5}, Vec3{0.5, 4, 0.5}, Vec3{-3, 4, 0.5}}, 1, 1,
                     {}, {});
    Settings st = Settings::preset("HIGH");
    st.rays_per_link = 128;  // the receiver stays one small element: its visibility is a ray estimate
    Solver solver(s, st);
    solver.solve();
    // Exact for the receiver's points: each sees the part of the emitter beyond the line
    // through the blocker edge; integrate that per receiver cell.
    double expect = 0;
    {
        std::vector<Poly> cells{rcv};
        for (int l = 0; l < 4; ++l) {
            std::vector<Poly> nx;
            for (auto& c : cells)
                for (int k = 0; k < 4; ++k) nx.push_back(c.child(k));
            cells.swap(nx);
        }
        double a = 0;
        for (auto& c : cells) {
            Vec3 x = c.centroid();
            double edge = 0.5 + (0.5 - x.x);  // the shadow line on the emitter plane (z=1)
            Poly vis = quad({edge, 0, 1}, {edge, 1, 1}, {1, 1, 1}, {1, 0, 1});
            expect += c.area() * point_polygon_form_factor(x, {0, 0, 1}, vis, vis.normal());
            a += c.area();
        }
        expect /= a;
    }
    double got = object_front_radiance(solver, 0).r / 0.5;
    EXPECT_NEAR(got, expect, 0.02 * expect);
    EXPECT_NEAR(expect, form_factor(rcv, half), 0.05 * expect);  // sanity: about half
}

TEST(SolverTransport, FullBlockerGivesZero) {
    SceneDesc s;
    scenes::add_grid(s, "receiver", -1, {Vec3{0, 0, 0}, Vec3{1, 0, 0}, Vec3{1, 1, 0}, Vec3{0, 1, 0}}, 2, 2, Rgb::all(0.5), {}, false);
    scenes::add_grid(s, "emitter", -1, {Vec3{0, 0, 1}, Vec3{0, 1, 1}, Vec3{1, 1, 1}, Vec3{1, 0, 1}}, 1, 1, {}, Rgb::all(1.0), false);
    scenes::add_grid(s, "blocker", -1, {Vec3{-5, -5, 0.5}, Vec3{6, -5, 0.5}, Vec3{6, 6, 0.5}, Vec3{-5, 6, 0.5}}, 1, 1, {}, {});
    Solver solver(s, Settings::preset("HIGH"));
    solver.solve();
    for (const Node* n : front_leaves(solver, 0)) EXPECT_EQ(n->L.r, 0.0);
}

TEST(SolverTransport, PlateCentreUnderSquareEmitter) {
    // NOTES.md: irradiance at height h below the centre of an a x b emitter of radiance L is
    // pi L F, F = 4 f(a/2h, b/2h). Plate radiance = rho * L * F.
    auto f = [](double x, double y) {
        return (x / std::sqrt(1 + x * x) * std::atan(y / std::sqrt(1 + x * x)) +
                y / std::sqrt(1 + y * y) * std::atan(x / std::sqrt(1 + y * y))) / (2 * kPi);
    };
    const double F = 4 * f(0.5, 0.5), L = 10, rho = 0.5;
    SceneDesc s;
    scenes::add_grid(s, "plate", -1, {Vec3{-2, -2, 0}, Vec3{2, -2, 0}, Vec3{2, 2, 0}, Vec3{-2, 2, 0}}, 8, 8, Rgb::all(rho), {});
    scenes::add_grid(s, "light", -1, {Vec3{-0.5, -0.5, 1}, Vec3{-0.5, 0.5, 1}, Vec3{0.5, 0.5, 1}, Vec3{0.5, -0.5, 1}}, 1, 1, {},
                     Rgb::all(L), false);
    // The solution's own leaf under the centre (the gathered corners are judged against the
    // point kernel in test_final_gather.cpp), refined with a scene-wide threshold of 0.01:
    // HIGH's 0.05 leaves a leaf whose average is 1.2 % under the peak at its corner.
    Settings st = Settings::preset("HIGH");
    st.error_threshold = 0.01;
    st.threshold_floor = 1.0;
    Solver solver(s, st);
    solver.solve();
    Rgb got = solver.radiance_at(0, 27, {0, 0, 0});  // face 27 touches the centre
    EXPECT_NEAR(got.r, rho * L * F, 0.01 * rho * L * F) << "analytic " << rho * L * F;
    EXPECT_NEAR(rho * L * F, 1.1973, 0.001);
}

TEST(AnalyticKernel, ReceiverCubatureKeepsOnlyTheFrontPart) {
    // A floor plate x in [-9, 1] under a wall in the plane x = 0 facing +x: the plain 2x2 rule
    // puts every point at x < 0, behind the wall.
    Poly floor = quad({-9, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-9, 1, 0});
    for (int k = 0; k < cubature(floor).n; ++k) ASSERT_LT(cubature(floor).p[k].x, 0.0);
    Cubature c = receiver_cubature(floor, {0, 0, 0}, {1, 0, 0});
    ASSERT_GT(c.n, 0);
    double w = 0;
    for (int k = 0; k < c.n; ++k) {
        EXPECT_GT(c.p[k].x, 0.0);
        w += c.w[k];
    }
    EXPECT_NEAR(w, 0.1, 1e-12);  // the front part's share of the area
    // Wholly in front (touching the plane at an edge): the plain rule.
    Poly front = quad({0, -1, 0}, {1, -1, 0}, {1, 1, 0}, {0, 1, 0});
    Cubature a = receiver_cubature(front, {0, 0, 0}, {1, 0, 0}), b = cubature(front);
    ASSERT_EQ(a.n, b.n);
    for (int k = 0; k < a.n; ++k) EXPECT_EQ(a.w[k], b.w[k]);
}

TEST(SolverTransport, ReceiverStraddlingTheSendersPlane) {
    // An emissive wall standing across a floor plate (x = 0, facing +x; the plate runs from
    // x = -9 behind it to x = 1 in front). Before receiver_cubature the plate's one link had
    // every cubature point behind the wall, coupling 0, and was dropped: the plate stayed
    // black however much of it faced the wall.
    const double L = 10, rho = 0.5;
    Poly wall = quad({0, -1, 0}, {0, 1, 0}, {0, 1, 2}, {0, -1, 2});  // normal +x
    ASSERT_NEAR(wall.normal().x, 1.0, 1e-12);
    SceneDesc s;
    scenes::add_grid(s, "floor", -1, {Vec3{-9, -1, 0}, Vec3{1, -1, 0}, Vec3{1, 1, 0}, Vec3{-9, 1, 0}}, 1, 1, Rgb::all(rho), {});
    scenes::add_grid(s, "wall", -1, {wall.v[0], wall.v[1], wall.v[2], wall.v[3]}, 1, 1, {}, Rgb::all(L), false);
    Settings st = Settings::preset("MEDIUM");
    st.closure_rays = 0;  // open scene: the raw transport
    Solver solver(s, st);
    solver.solve();
    // Exact: the area-mean kernel over the plate; its part behind the wall gets nothing.
    double expect = 0;
    const int n = 400;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            Vec3 x{(i + 0.5) / n, -1 + 2 * (j + 0.5) / n, 0};
            expect += point_polygon_form_factor(x, {0, 0, 1}, wall, wall.normal()) / (n * n);
        }
    expect *= 1.0 / 10.0;  // the front part is a tenth of the plate
    EXPECT_NEAR(object_front_radiance(solver, 0).r, rho * L * expect, 0.03 * rho * L * expect);
}

// A sender's outline across the receiver, 1 cm over it (a lamp under a ceiling): the kernel
// steps from about 1 to 0 within the receiver, where four Gauss points read the coupling as
// 0.50 whether the sender covers 30 % or 70 % of it. The receiver cubature of its
// descendants follows the step.
TEST(AnalyticKernel, DenseCouplingFollowsAnOutlineAcrossTheReceiver) {
    const Poly r = quad({0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0});
    for (double x0 : {0.3, 0.7}) {
        Node s;
        s.poly = quad({x0, -1, 0.01}, {x0, 2, 0.01}, {x0 + 3, 2, 0.01}, {x0 + 3, -1, 0.01});  // facing -z
        s.normal = s.poly.normal();
        constexpr int N = 200;
        double ref = 0;
        for (int i = 0; i < N; ++i)
            for (int j = 0; j < N; ++j)
                ref += point_polygon_form_factor({(i + 0.5) / N, (j + 0.5) / N, 0}, {0, 0, 1}, s.poly, s.normal);
        ref /= N * N;
        EXPECT_NEAR(ref, 1.0 - x0, 0.01);
        EXPECT_NEAR(unoccluded_coupling(r, {0, 0, 1}, s, 2), ref, 0.02 * ref) << "sender from x = " << x0;
        EXPECT_GT(std::fabs(unoccluded_coupling(r, {0, 0, 1}, s) - ref), 0.1 * ref) << "the 4-point rule was exact here";
    }
}

// The same through the solver, with an element floor of a third of the receiver: the receiver's
// coupling to an emitter covering 70 % of it, 1 cm above.
TEST(SolverTransport, CoarseReceiverUnderAnEmitterOutline) {
    Settings st = Settings::preset("MEDIUM");
    st.closure_rays = 0;
    st.gather_rays = 0;
    const Poly rcv = quad({0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0});
    const Poly src = quad({0.3, -1, 0.01}, {0.3, 2, 0.01}, {3.3, 2, 0.01}, {3.3, -1, 0.01});
    const double diag2 = 3.3 * 3.3 + 3 * 3 + 0.01 * 0.01;
    st.min_area_fraction = 0.3 / diag2;
    EXPECT_NEAR(solved_form_factor(rcv, src, st), 0.70, 0.02);
}

// coupling_bound, which lets the oracle keep a link whose point model fails while the light it
// may carry is small, must bound the coupling at every receiving point: here against the
// unoccluded form factor from P's surfaces, at the corners and centre of each surface of Q,
// over every pair of nodes of a wall with a box 5 cm before it and a floor whose boxes do not
// meet.
TEST(CouplingBound, BoundsTheCouplingAtEveryReceivingPoint) {
    SceneDesc s;
    scenes::add_grid(s, "wall", -1, {Vec3{0, 0, 0}, Vec3{0, 4, 0}, Vec3{0, 4, 2.5}, Vec3{0, 0, 2.5}}, 16, 10, Rgb::all(0.6),
                     {}, false);
    scenes::add_grid(s, "floor", -1, {Vec3{0.01, 0, 0}, Vec3{4, 0, 0}, Vec3{4, 4, 0}, Vec3{0.01, 4, 0}}, 8, 8, Rgb::all(0.6),
                     {}, false);
    scenes::add_box(s, "box", -1, {0.05, 1.0, 0.3}, {0.55, 2.2, 1.1}, 3, Rgb::all(0.6), {});
    Hierarchy h;
    h.build(s, true);
    // Split a few levels of elements so that pairs of elements and clusters of each size occur.
    for (int pass = 0; pass < 2; ++pass)
        for (size_t id = 0, n = h.nodes.size(); id < n; ++id)
            if (!h.nodes[id].is_cluster()) h.subdivide(int(id));
    // What a point y (normal ny) below Q receives from P's surfaces facing it, unoccluded.
    auto coupling_at = [&](const Node& P, const Vec3& y, const Vec3& ny) {
        double k = 0;
        auto add = [&](const Poly& poly, const Vec3& normal) {
            if (dot(y - poly.v[0], normal) > 0) k += std::max(0.0, point_polygon_form_factor(y, ny, poly, normal));
        };
        if (!P.is_cluster()) add(P.poly, P.normal);
        else
            for (int i = P.surf_begin; i < P.surf_end; ++i) add(h.surface_geom[size_t(i)].poly, h.surface_geom[size_t(i)].normal);
        return k;
    };
    Rng rng(7);
    int checked = 0, small = 0;
    for (int trial = 0; trial < 20000 && checked < 3000; ++trial) {
        const int a = int(rng.next() * double(h.nodes.size())), b = int(rng.next() * double(h.nodes.size()));
        const Node& P = h.nodes[size_t(a)];
        const Node& Q = h.nodes[size_t(b)];
        if (a == b || P.box.overlaps(Q.box)) continue;
        const double bound = coupling_bound(h, a, b);
        std::vector<std::pair<Poly, Vec3>> rcv;
        if (!Q.is_cluster()) rcv.push_back({Q.poly, Q.normal});
        else
            for (int i = Q.surf_begin; i < Q.surf_end; ++i) rcv.push_back({h.surface_geom[size_t(i)].poly, h.surface_geom[size_t(i)].normal});
        double worst = 0;
        for (const auto& [poly, n] : rcv) {
            worst = std::max(worst, coupling_at(P, poly.centroid(), n));
            for (int k = 0; k < poly.n; ++k)
                worst = std::max(worst, coupling_at(P, poly.v[size_t(k)] + (poly.centroid() - poly.v[size_t(k)]) * 1e-3, n));
        }
        ASSERT_GE(bound, worst * (1 - 1e-9)) << "nodes " << a << " -> " << b;
        ++checked;
        small += bound < 0.01;
    }
    EXPECT_GE(checked, 3000);
    EXPECT_GT(small, 100);  // the bound is useful: well under 1 for many pairs apart
}
