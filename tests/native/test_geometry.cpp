// The clip of a polygon at a plane (front_part) against a reference computed another way, for
// every way a plane can cross a triangle, a planar quad and a warped quad (Bevel and
// Subdivision Surface make quads that are planar only to about 1e-4 of their size, and a plane
// nearly containing one crosses it four times). Also the stratified cosine directions of
// CosineStrata, draw for draw, and the window of them that may meet a box (CosineWindow).
// Also a box grown by a margin (Aabb::grown), the cube about a point (Aabb::around) and the
// shaft test between two boxes (Aabb::meets_shaft).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

#include "radiosity/random.h"
#include "test_util.h"

using namespace radiosity;
using namespace radiosity::testing;

namespace {

// Area of the part of triangle (a, b, c) where the signed distance is > 0, from the closed
// form for a linear function over a triangle (not by clipping): one vertex in front keeps
// the corner triangle scaled by the two edge fractions, two in front lose such a corner.
double reference_tri_front_area(const Vec3& a, const Vec3& b, const Vec3& c, double da, double db, double dc) {
    const double area = 0.5 * length(cross(b - a, c - a));
    const Vec3 v[3] = {a, b, c};
    const double d[3] = {da, db, dc};
    int front = 0;
    for (double x : d) front += x > 0;
    if (front == 0) return 0;
    if (front == 3) return area;
    for (int i = 0; i < 3; ++i) {
        const double di = d[i], dj = d[(i + 1) % 3], dk = d[(i + 2) % 3];
        if (front == 1 && di > 0) return area * (di / (di - dj)) * (di / (di - dk));
        if (front == 2 && !(di > 0)) return area * (1 - (di / (di - dj)) * (di / (di - dk)));
    }
    (void)v;
    return -1;
}

// The reference front area of a polygon as Poly reads it: a quad is triangles (0,1,2), (0,2,3).
double reference_front_area(const Poly& p, const Vec3& x, const Vec3& nx) {
    auto d = [&](int i) { return dot(p.v[size_t(i)] - x, nx); };
    double a = reference_tri_front_area(p.v[0], p.v[1], p.v[2], d(0), d(1), d(2));
    if (p.n == 4) a += reference_tri_front_area(p.v[0], p.v[2], p.v[3], d(0), d(2), d(3));
    return a;
}

// Distance from s to triangle (a, b, c) when s projects inside it (else infinity).
double distance_on_triangle(const Vec3& s, const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 n = cross(b - a, c - a);
    const double n2 = length2(n);
    if (!(n2 > 0)) return INFINITY;
    const double tol = -1e-9 * n2;
    if (dot(cross(b - a, s - a), n) < tol || dot(cross(c - b, s - b), n) < tol || dot(cross(a - c, s - c), n) < tol)
        return INFINITY;
    return std::fabs(dot(s - a, n)) / std::sqrt(n2);
}

// A random rotation (unit quaternion) applied about the origin.
struct Rotation {
    double m[9];
    explicit Rotation(std::mt19937_64& g) {
        std::normal_distribution<double> N;
        double q[4];
        double l = 0;
        for (double& x : q) x = N(g), l += x * x;
        l = std::sqrt(l);
        for (double& x : q) x /= l;
        const double w = q[0], x = q[1], y = q[2], z = q[3];
        const double r[9] = {1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y),
                             2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
                             2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)};
        for (int i = 0; i < 9; ++i) m[i] = r[i];
    }
    Vec3 operator()(const Vec3& v) const {
        return {m[0] * v.x + m[1] * v.y + m[2] * v.z, m[3] * v.x + m[4] * v.y + m[5] * v.z,
                m[6] * v.x + m[7] * v.y + m[8] * v.z};
    }
};

// Checks front_part(p, x, nx) against the reference: its area, that every sample lies in
// front of the plane and on the polygon's surface, and that samples spread by area over the
// polygon's two triangles (the stratified u1 must reach every piece in proportion).
// exact = false: the quad is planar to within front_part's tolerance and the plane nearly
// contains it, so where the cut runs is ill-conditioned (the whole quad's clip and its two
// triangles' clips differ there, both valid): only the bounds, the side and the surface count.
void expect_exact_clip(const Poly& p, const Vec3& x, const Vec3& nx, const std::string& what, bool exact = true) {
    const FrontPart f = front_part(p, x, nx);
    const double ref = reference_front_area(p, x, nx);
    const double size = std::sqrt(p.area());
    ASSERT_LE(f.n, 4) << what;
    if (!exact) {
        EXPECT_GE(f.area, 0.0) << what;
        EXPECT_LE(f.area, p.area() * (1 + 1e-12)) << what;
        for (int k = 0; k < 200 && f.n > 0; ++k) {
            const Vec3 s = f.sample((k + 0.5) / 200, std::fmod(k * 0.618034, 1.0));
            EXPECT_GE(dot(s - x, nx), -1e-12 * size) << what;
            const double d0 = distance_on_triangle(s, p.v[0], p.v[1], p.v[2]);
            const double d1 = distance_on_triangle(s, p.v[0], p.v[2], p.v[3]);
            ASSERT_LE(std::min(d0, d1), 1e-8 * size) << what;
        }
        return;
    }
    if (ref <= 1e-12 * size * size) {
        EXPECT_NEAR(f.area, 0.0, 1e-9 * size * size) << what;
        return;
    }
    ASSERT_GT(f.n, 0) << what;
    EXPECT_NEAR(f.area, ref, 1e-9 * size * size) << what;
    const Vec3 t0[3] = {p.v[0], p.v[1], p.v[2]}, t1[3] = {p.v[0], p.v[2], p.v[3]};
    const double ref0 = reference_tri_front_area(t0[0], t0[1], t0[2], dot(t0[0] - x, nx), dot(t0[1] - x, nx),
                                                 dot(t0[2] - x, nx));
    const int samples = 4000;
    int on_first = 0, on_both = 0;
    for (int k = 0; k < samples; ++k) {
        const double u1 = (k + 0.5) / samples, u2 = std::fmod(k * 0.6180339887498949, 1.0);
        const Vec3 s = f.sample(u1, u2);
        EXPECT_GE(dot(s - x, nx), -1e-12 * size) << what << " sample " << k << " behind the plane";
        const double d0 = distance_on_triangle(s, t0[0], t0[1], t0[2]);
        const double d1 = p.n == 4 ? distance_on_triangle(s, t1[0], t1[1], t1[2]) : INFINITY;
        const double d = std::min(d0, d1);
        ASSERT_LE(d, 1e-8 * size) << what << " sample " << k << " off the polygon's surface";
        if (p.n == 4 && d0 < d1) ++on_first;
        if (p.n == 4 && d0 == d1) ++on_both;
    }
    // (A planar concave quad's triangles can overlap: no share to check there.)
    if (p.n == 4 && on_both == 0) EXPECT_NEAR(double(on_first) / samples, ref0 / ref, 0.01) << what << ": samples not spread by area";
}

}  // namespace

TEST(FrontPart, TriangleEveryCrossing) {
    // A plane through each subset of a triangle's vertices' sides.
    const Poly t = [] {
        Poly p;
        p.n = 3;
        p.v = {Vec3{0, 0, 0}, Vec3{2, 0, 0.3}, Vec3{0.5, 1.5, -0.2}, Vec3{}};
        return p;
    }();
    const Vec3 nx = normalize(Vec3{0.3, -0.2, 1});
    for (int mask = 0; mask < 8; ++mask) {
        // Each vertex lifted above or below the plane z' = 0 by a twisted height.
        Poly q = t;
        for (int i = 0; i < 3; ++i) q.v[size_t(i)] = q.v[size_t(i)] + nx * ((mask >> i & 1) ? 0.4 : -0.3);
        expect_exact_clip(q, {0.7, 0.4, 0}, nx, "triangle pattern " + std::to_string(mask));
    }
}

TEST(FrontPart, WarpedQuadEveryCrossingPattern) {
    // A unit quad whose corners sit +-w off the plane z = 0 in every sign pattern (the
    // alternating ones cross the plane four times), for warps from a rounding error to a
    // strongly bent quad, in random orientations and positions. Below 1e-9 of its size a quad
    // counts as planar and is clipped whole.
    std::mt19937_64 g(7);
    std::uniform_real_distribution<double> U(-1, 1);
    for (double w : {1e-12, 1e-6, 1e-4, 0.05, 0.4})
        for (int mask = 0; mask < 16; ++mask)
            for (int orient = 0; orient < 4; ++orient) {
                const Rotation R(g);
                const Vec3 at{U(g) * 10, U(g) * 10, U(g) * 10};
                const double h[4] = {(mask & 1) ? w : -w, (mask & 2) ? w : -w, (mask & 4) ? w : -w, (mask & 8) ? w : -w};
                // Unequal magnitudes so crossings are not at edge midpoints.
                const double s[4] = {1.0, 0.6, 1.3, 0.8};
                const Vec3 base[4] = {{0, 0, 0}, {1, 0, 0}, {1.1, 0.9, 0}, {-0.1, 1, 0}};
                Poly q;
                q.n = 4;
                for (int i = 0; i < 4; ++i) q.v[size_t(i)] = R(base[i] + Vec3{0, 0, h[i] * s[i]}) + at;
                const Vec3 x = R(Vec3{0.45, 0.5, 0}) + at, nx = R(Vec3{0, 0, 1});
                const std::string what = "w " + std::to_string(w) + " pattern " + std::to_string(mask);
                // Four crossings are exact at any warp; two only beyond the planarity tolerance.
                const bool exact = w > 1e-9 || mask == 5 || mask == 10;
                expect_exact_clip(q, x, nx, what, exact);
                expect_exact_clip(q, x, nx * -1.0, what + " (other side)", exact);
            }
}

TEST(FrontPart, RandomPlanesAndQuads) {
    // Arbitrary planes against planar, warped and concave quads and triangles.
    std::mt19937_64 g(11);
    std::uniform_real_distribution<double> U(-1, 1);
    for (int trial = 0; trial < 3000; ++trial) {
        Poly p;
        p.n = trial % 3 == 0 ? 3 : 4;
        for (int i = 0; i < p.n; ++i) p.v[size_t(i)] = Vec3{U(g), U(g), (trial % 3 == 1) ? 0.0 : 0.2 * U(g)};
        const Vec3 x{U(g) * 0.5, U(g) * 0.5, U(g) * 0.5};
        const Vec3 nx = normalize(Vec3{U(g), U(g), U(g)});
        if (!(p.area() > 1e-3)) continue;
        expect_exact_clip(p, x, nx, "trial " + std::to_string(trial));
    }
}

TEST(FrontPart, PlanarConvexQuadIsClippedWhole) {
    // The usual case: a plane crossing a planar convex quad twice gives one convex piece,
    // fanned into at most three triangles.
    const Poly q = quad({0, 0, 0}, {2, 0, 0}, {2, 1, 0}, {0, 1, 0});
    const Vec3 x{0.5, 0.5, 0}, nx = normalize(Vec3{1, 0.3, 0});
    EXPECT_LE(front_part(q, x, nx).n, 3);
    expect_exact_clip(q, x, nx, "planar");
}

TEST(FrontPart, QuadWhollyInFrontIsItsTwoTriangles) {
    // Sampled as Poly::sample samples it: the same points for the same (u1, u2).
    const Poly q = quad({0, 0, 0}, {2, 0, 0}, {2.2, 1, 0.1}, {0, 1, 0});
    const FrontPart f = front_part(q, {1, 0.5, -1}, {0, 0, 1});
    ASSERT_EQ(f.n, 2);
    EXPECT_DOUBLE_EQ(f.area, q.area());
    for (double u1 : {0.05, 0.3, 0.6, 0.95})
        for (double u2 : {0.1, 0.7}) {
            const Vec3 a = f.sample(u1, u2), b = q.sample(u1, u2);
            EXPECT_NEAR(length(a - b), 0.0, 1e-12);
        }
}

TEST(FrontPart, NonFiniteOrDegenerateInputGivesNothing) {
    const Poly q = quad({0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0});
    EXPECT_EQ(front_part(q, {NAN, 0, 0}, {1, 0, 0}).n, 0);
    EXPECT_EQ(front_part(q, {0.5, 0.5, 0}, {NAN, NAN, NAN}).n, 0);
    EXPECT_EQ(front_part(q, {0.5, 0.5, 0}, {0, 0, 0}).n, 0);
    const Poly flat = quad({0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0});  // zero area
    EXPECT_EQ(front_part(flat, {0, -1, 0}, {0, 1, 0}).n, 0);
    Poly bad = q;
    bad.n = 7;  // not a Poly the hierarchy makes: refused, not read past its four vertices
    EXPECT_EQ(front_part(bad, {0.5, 0.5, -1}, {0, 0, 1}).n, 0);
}

TEST(FrontPart, ReceiverCubatureOfAWarpedQuadSumsToItsFrontShare) {
    // The four-crossing case feeds receiver_cubature four triangles: every weight counted.
    Poly q = quad({0, 0, 1e-5}, {1, 0, -1e-5}, {1, 1, 1e-5}, {0, 1, -1e-5});
    const Vec3 x{0.5, 0.5, 0}, nx{0, 0, 1};
    const Cubature c = receiver_cubature(q, x, nx);
    double w = 0;
    for (int k = 0; k < c.n; ++k) {
        w += c.w[size_t(k)];
        EXPECT_GT(dot(c.p[size_t(k)] - x, nx), 0.0);
    }
    EXPECT_NEAR(w, reference_front_area(q, x, nx) / q.area(), 1e-9);
}

TEST(CosineStrata, DrawsTheAzimuthThenThePolarNumberOfEachStratum) {
    // The hemisphere loops (escape rays, probes, the near field's s*) cast these rays and
    // record or replay them: the directions, and the order of the draws, must stay as they are.
    const Vec3 n = normalize(Vec3{0.3, -0.2, 0.9});
    Vec3 u, v;
    frame(n, u, v);
    for (int side : {1, 4, 6, 8}) {
        const CosineStrata strata(n, side);
        ASSERT_EQ(strata.count(), side * side);
        Rng a(11), b(11);
        for (int i = 0; i < strata.count(); ++i) {
            const Vec3 d = strata.direction(i, a);
            const double r1 = (i % side + b.next()) / side;
            const double r2 = (i / side + b.next()) / side;
            const Vec3 e = cosine_direction(u, v, n, r1, r2);
            EXPECT_EQ(d.x, e.x);
            EXPECT_EQ(d.y, e.y);
            EXPECT_EQ(d.z, e.z);
            EXPECT_NEAR(length(d), 1.0, 1e-12);
            EXPECT_GE(dot(d, n), 0.0);
        }
    }
}

TEST(CosineWindow, HoldsEveryDirectionWhoseRayMeetsTheBox) {
    // A replay keeps a uniform sky's sample outside the window without making its ray: every
    // ray from the ball of origins that meets the box must lie inside. Random boxes, balls and
    // planes, near (boxes over the pole, at the horizon, around the origins) and far.
    std::mt19937_64 g(5);
    std::uniform_real_distribution<double> U(0.0, 1.0);
    auto uvec = [&](double s) { return Vec3{U(g) - 0.5, U(g) - 0.5, U(g) - 0.5} * (2 * s); };
    int met = 0, outside = 0, samples = 0;
    for (int trial = 0; trial < 400; ++trial) {
        const Vec3 n = normalize(uvec(1.0) + Vec3{0, 0, 1e-3});
        Vec3 nu, nv;
        frame(n, nu, nv);
        const Vec3 c = uvec(1.0);
        const double r = trial % 3 == 0 ? 0.0 : 0.3 * U(g);
        Aabb box;
        const double far = trial % 2 ? 1.0 : 20.0;
        const Vec3 b0 = c + uvec(far);
        box.grow(b0);
        box.grow(b0 + Vec3{U(g), U(g), U(g)} * (0.2 + far * 0.1));
        const CosineWindow w(box, c, r, nu, nv, n);
        for (int k = 0; k < 3000; ++k) {
            const double r1 = U(g), r2 = U(g);
            const Vec3 d = cosine_direction(nu, nv, n, r1, r2);
            const Vec3 o = c + uvec(r) * (1.0 / std::sqrt(3.0));  // within the ball
            const bool meets = box.meets_segment(o, o + d * 100.0);
            ++samples;
            met += meets;
            if (!w.may_meet(r1, r2)) {
                ++outside;
                ASSERT_FALSE(meets) << "trial " << trial << " sample " << k;
            }
        }
    }
    // The window is a test worth making: most samples of a small, far box fall outside it.
    EXPECT_GT(met, 1000);
    EXPECT_GT(outside, samples / 2);
    std::printf("[ figure ] %d of %d samples outside their window, %d rays met the box\n", outside, samples, met);
    // Nothing moved: every sample keeps its outcome; no box: CosineWindow() keeps none.
    EXPECT_FALSE(CosineWindow(Aabb{}, Vec3{}, 0.1, Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, 0, 1}).may_meet(0.3, 0.3));
    EXPECT_TRUE(CosineWindow().may_meet(0.3, 0.3));
}

TEST(Aabb, GrownMovesEverySideOutByTheMargin) {
    Aabb b;
    b.grow(Vec3{-1, 0.5, 2});
    b.grow(Vec3{3, 0.75, 4});
    const double tol = 0.125;
    const Aabb g = b.grown(tol);
    // Each side is exactly lo - tol or hi + tol, bit for bit.
    EXPECT_EQ(g.lo.x, -1 - tol);
    EXPECT_EQ(g.lo.y, 0.5 - tol);
    EXPECT_EQ(g.lo.z, 2 - tol);
    EXPECT_EQ(g.hi.x, 3 + tol);
    EXPECT_EQ(g.hi.y, 0.75 + tol);
    EXPECT_EQ(g.hi.z, 4 + tol);
    // The box itself is left as it was.
    EXPECT_EQ(b.lo.x, -1.0);
    EXPECT_EQ(b.hi.z, 4.0);
    // A point a margin away is in the grown box and not in the box; one farther is in neither.
    EXPECT_FALSE(b.contains(Vec3{3.1, 0.6, 3}));
    EXPECT_TRUE(g.contains(Vec3{3.1, 0.6, 3}));
    EXPECT_FALSE(g.contains(Vec3{3.2, 0.6, 3}));
    // A point's box grows into a cube around it; a zero margin changes nothing.
    Aabb p;
    p.grow(Vec3{1, 2, 3});
    const Aabb c = p.grown(0.5);
    EXPECT_EQ(c.lo.x, 0.5);
    EXPECT_EQ(c.hi.z, 3.5);
    const Aabb same = b.grown(0.0);
    EXPECT_EQ(same.lo.y, b.lo.y);
    EXPECT_EQ(same.hi.y, b.hi.y);
}

TEST(Aabb, GrownEmptyBoxStaysEmpty) {
    // However large the margin (one past the empty box's sentinels would turn it inside out):
    // an empty box holds no point to grow around, and a box grown from it meets nothing.
    for (double tol : {0.0, 1e-5, 1.0, 1e301, std::numeric_limits<double>::infinity()}) {
        const Aabb g = Aabb{}.grown(tol);
        EXPECT_TRUE(g.empty()) << tol;
        EXPECT_EQ(g.diagonal(), 0.0) << tol;
        EXPECT_FALSE(g.contains(Vec3{0, 0, 0})) << tol;
        Aabb unit;
        unit.grow(Vec3{0, 0, 0});
        unit.grow(Vec3{1, 1, 1});
        EXPECT_FALSE(g.overlaps(unit)) << tol;
    }
}

TEST(Aabb, IntersectionIsTheBoxOfThePointsInBoth) {
    Aabb unit;
    unit.grow(Vec3{0, 0, 0});
    unit.grow(Vec3{1, 1, 1});
    auto box = [](Vec3 lo, Vec3 hi) { return Aabb{lo, hi}; };
    // Each side is the inner of the two sides, bit for bit, whichever box asks.
    const Aabb b = box({0.5, -1, 0.25}, {2, 0.375, 0.75});
    for (const auto& m : {unit.intersection(b), b.intersection(unit)}) {
        ASSERT_TRUE(m.has_value());
        EXPECT_EQ(m->lo.x, 0.5);
        EXPECT_EQ(m->lo.y, 0.0);
        EXPECT_EQ(m->lo.z, 0.25);
        EXPECT_EQ(m->hi.x, 1.0);
        EXPECT_EQ(m->hi.y, 0.375);
        EXPECT_EQ(m->hi.z, 0.75);
    }
    // Boxes that touch meet in a flat box; boxes apart on any one axis (here y alone, where
    // empty()'s test of x would not tell) do not meet, and an empty box meets nothing.
    const auto flat = unit.intersection(box({1, 0, 0}, {2, 1, 1}));
    ASSERT_TRUE(flat.has_value());
    EXPECT_EQ(flat->lo.x, 1.0);
    EXPECT_EQ(flat->hi.x, 1.0);
    EXPECT_FALSE(unit.intersection(box({0, 2, 0}, {1, 3, 1})).has_value());
    EXPECT_FALSE(unit.intersection(box({0, 0, -3}, {1, 1, -2})).has_value());
    EXPECT_FALSE(unit.intersection(Aabb{}).has_value());
    EXPECT_FALSE(Aabb{}.intersection(unit).has_value());
    // Between boxes that hold points, they meet exactly when overlaps() says so.
    Rng rng(3);
    for (int t = 0; t < 1000; ++t) {
        Aabb p, q;
        for (Aabb* x : {&p, &q})
            for (int k = 0; k < 2; ++k) x->grow(Vec3{rng.next() * 4, rng.next() * 4, rng.next() * 4});
        const auto m = p.intersection(q);
        EXPECT_EQ(m.has_value(), p.overlaps(q)) << t;
        if (m) EXPECT_TRUE(m->contains(m->center())) << t;
    }
}

TEST(Aabb, Distance2IsTheSquaredGapBetweenTheNearestPoints) {
    const Aabb unit{Vec3{0, 0, 0}, Vec3{1, 1, 1}};
    // Apart on two axes: the gaps' squares add up, whichever box asks; meeting or touching: 0.
    const Aabb b{Vec3{3, 0.5, -4}, Vec3{5, 2, -2}};
    EXPECT_EQ(unit.distance2(b), 2.0 * 2.0 + 2.0 * 2.0);
    EXPECT_EQ(b.distance2(unit), unit.distance2(b));
    EXPECT_EQ(unit.distance2(Aabb{Vec3{1, 1, 1}, Vec3{2, 2, 2}}), 0.0);
    EXPECT_EQ(unit.distance2(Aabb{Vec3{0.5, 0.5, 0.5}, Vec3{0.6, 0.6, 0.6}}), 0.0);
    // Against points drawn in each box: never more than any pair's distance, and reached by
    // the nearest corners when the boxes are apart on every axis.
    Rng rng(5);
    for (int t = 0; t < 200; ++t) {
        Aabb p, q;
        for (int k = 0; k < 2; ++k) p.grow(Vec3{rng.next() * 2, rng.next() * 2, rng.next() * 2});
        for (int k = 0; k < 2; ++k) q.grow(Vec3{rng.next() * 2 + 1, rng.next() * 2 + 1, rng.next() * 2 + 1});
        for (int k = 0; k < 20; ++k) {
            const Vec3 x = p.lo + (p.hi - p.lo) * rng.next(), y = q.lo + (q.hi - q.lo) * rng.next();
            EXPECT_LE(p.distance2(q), length2(x - y) * (1 + 1e-12)) << t;
        }
    }
    const Aabb far{Vec3{4, 5, 6}, Vec3{7, 8, 9}};
    EXPECT_DOUBLE_EQ(unit.distance2(far), length2(far.lo - unit.hi));
}

TEST(Aabb, GrownPerAxisMovesEachAxisByItsOwnMargin) {
    Aabb b;
    b.grow(Vec3{-1, 0.5, 2});
    b.grow(Vec3{3, 0.75, 4});
    // Each side is exactly lo - t[a] or hi + t[a], bit for bit; a zero keeps that axis.
    const Vec3 t{0.125, 0.0, 0.5};
    const Aabb g = b.grown(t);
    EXPECT_EQ(g.lo.x, -1 - 0.125);
    EXPECT_EQ(g.lo.y, 0.5);
    EXPECT_EQ(g.lo.z, 2 - 0.5);
    EXPECT_EQ(g.hi.x, 3 + 0.125);
    EXPECT_EQ(g.hi.y, 0.75);
    EXPECT_EQ(g.hi.z, 4 + 0.5);
    // The same margin on every axis is grown(double), side for side.
    Rng rng(7);
    for (int k = 0; k < 100; ++k) {
        const double r = rng.next() * (k % 2 ? 1e-5 : 3.0);
        const Aabb u = b.grown(Vec3{r, r, r}), v = b.grown(r);
        for (int a = 0; a < 3; ++a) {
            EXPECT_EQ(u.lo[a], v.lo[a]);
            EXPECT_EQ(u.hi[a], v.hi[a]);
        }
    }
    // An empty box stays empty.
    EXPECT_TRUE(Aabb{}.grown(Vec3{1e301, 1, 1e301}).empty());
    EXPECT_FALSE(Aabb{}.grown(Vec3{1e301, 1e301, 1e301}).contains(Vec3{0, 0, 0}));
}

TEST(Aabb, AroundIsTheCubeAboutAPoint) {
    // Each side is p - r and p + r, one subtraction and one addition, bit for bit, and the
    // same as a one-point box grown by r.
    Rng rng(5);
    for (int t = 0; t < 1000; ++t) {
        const Vec3 p{rng.next() * 20 - 10, rng.next() * 1e-3, rng.next() * 1e6};
        const double r = rng.next() * (t % 2 ? 1e-5 : 3.0);
        const Aabb c = Aabb::around(p, r);
        Aabb point;
        point.grow(p);
        const Aabb g = point.grown(r);
        for (int a = 0; a < 3; ++a) {
            EXPECT_EQ(c.lo[a], p[a] - r);
            EXPECT_EQ(c.hi[a], p[a] + r);
            EXPECT_EQ(c.lo[a], g.lo[a]);
            EXPECT_EQ(c.hi[a], g.hi[a]);
        }
        EXPECT_TRUE(c.contains(p));
    }
    const Aabb c = Aabb::around(Vec3{1, 2, 3}, 0.5);
    EXPECT_EQ(c.lo.x, 0.5);
    EXPECT_EQ(c.hi.z, 3.5);
    EXPECT_TRUE(c.contains(Vec3{1.5, 1.5, 3.5}));  // a corner
    EXPECT_FALSE(c.contains(Vec3{1.6, 2, 3}));
    // A zero half-side is the point alone: not empty, and it holds the point.
    const Aabb point = Aabb::around(Vec3{1, 2, 3}, 0.0);
    EXPECT_FALSE(point.empty());
    EXPECT_TRUE(point.contains(Vec3{1, 2, 3}));
    EXPECT_EQ(point.diagonal(), 0.0);
}

TEST(Aabb, ShaftTestIsConservativeAndTight) {
    // Aabb::meets_shaft (the probe's filter before a link's dry run): whenever a segment
    // between the two boxes passes through the third, it says so; and it rejects a box
    // beside the thin end that the capsule about the centres' segment would keep.
    Rng rng(11);
    auto box = [&](double s) {
        Aabb b;
        Vec3 c{rng.next() * 4, rng.next() * 4, rng.next() * 4};
        Vec3 e{rng.next() * s, rng.next() * s, rng.next() * s};
        b.grow(c - e);
        b.grow(c + e);
        return b;
    };
    int hits = 0;
    for (int t = 0; t < 2000; ++t) {
        Aabb a = box(1.5), b = box(0.2), c = box(0.6);
        bool seen = false;
        for (int k = 0; k < 200 && !seen; ++k) {
            auto in = [&](const Aabb& x) {
                return Vec3{x.lo.x + rng.next() * (x.hi.x - x.lo.x), x.lo.y + rng.next() * (x.hi.y - x.lo.y),
                            x.lo.z + rng.next() * (x.hi.z - x.lo.z)};
            };
            seen = c.meets_segment(in(a), in(b));
        }
        hits += seen;
        if (seen) EXPECT_TRUE(c.meets_shaft(a, b)) << "trial " << t;
    }
    EXPECT_GT(hits, 100);  // the trials do exercise hits
    // A tall wall-like box a, a small box b far away, c just beside b off the hull.
    Aabb a, b, c;
    a.grow({0, 0, 0}), a.grow({0.1, 4, 4});
    b.grow({10, 1.9, 1.9}), b.grow({10.2, 2.1, 2.1});
    c.grow({9.5, 3.0, 1.9}), c.grow({9.7, 3.4, 2.1});
    EXPECT_FALSE(c.meets_shaft(a, b));
    b.grow({10.2, 3.5, 2.1});  // b now reaches over c: c lies in the hull
    EXPECT_TRUE(c.meets_shaft(a, b));
}
