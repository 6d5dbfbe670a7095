// Small value types shared by every module: 3-vectors (geometry) and RGB triples (radiometry).
#pragma once
#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

namespace radiosity {

struct Vec3 {
    double x = 0, y = 0, z = 0;
    Vec3() = default;
    constexpr Vec3(double x_, double y_, double z_) : x(x_), y(y_), z(z_) {}
    double operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
    double& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
    Vec3 operator+(const Vec3& o) const { return {x + o.x, y + o.y, z + o.z}; }
    Vec3 operator-(const Vec3& o) const { return {x - o.x, y - o.y, z - o.z}; }
    Vec3 operator-() const { return {-x, -y, -z}; }
    Vec3 operator*(double s) const { return {x * s, y * s, z * s}; }
    Vec3 operator/(double s) const { return {x / s, y / s, z / s}; }
    Vec3& operator+=(const Vec3& o) { x += o.x; y += o.y; z += o.z; return *this; }
    Vec3& operator-=(const Vec3& o) { x -= o.x; y -= o.y; z -= o.z; return *this; }
    Vec3& operator*=(double s) { x *= s; y *= s; z *= s; return *this; }
};
inline Vec3 operator*(double s, const Vec3& v) { return v * s; }
inline double dot(const Vec3& a, const Vec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Vec3 cross(const Vec3& a, const Vec3& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double length(const Vec3& v) { return std::sqrt(dot(v, v)); }
inline double length2(const Vec3& v) { return dot(v, v); }
inline Vec3 normalize(const Vec3& v) {
    double l = length(v);
    return l > 0 ? v / l : Vec3{0, 0, 0};
}
inline bool finite(const Vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
inline Vec3 vmin(const Vec3& a, const Vec3& b) { return {std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)}; }
inline Vec3 vmax(const Vec3& a, const Vec3& b) { return {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)}; }

// RGB radiometric triple (radiance, reflectance, gathered irradiance / pi).
struct Rgb {
    double r = 0, g = 0, b = 0;
    Rgb() = default;
    constexpr Rgb(double r_, double g_, double b_) : r(r_), g(g_), b(b_) {}
    static constexpr Rgb all(double v) { return {v, v, v}; }
    double operator[](int i) const { return i == 0 ? r : (i == 1 ? g : b); }
    double& operator[](int i) { return i == 0 ? r : (i == 1 ? g : b); }
    Rgb operator+(const Rgb& o) const { return {r + o.r, g + o.g, b + o.b}; }
    Rgb operator-(const Rgb& o) const { return {r - o.r, g - o.g, b - o.b}; }
    Rgb operator*(const Rgb& o) const { return {r * o.r, g * o.g, b * o.b}; }
    Rgb operator*(double s) const { return {r * s, g * s, b * s}; }
    Rgb operator/(double s) const { return {r / s, g / s, b / s}; }
    Rgb& operator+=(const Rgb& o) { r += o.r; g += o.g; b += o.b; return *this; }
    Rgb& operator*=(double s) { r *= s; g *= s; b *= s; return *this; }
    double max() const { return std::max(r, std::max(g, b)); }
    double mean() const { return (r + g + b) / 3.0; }
    bool is_zero() const { return r == 0 && g == 0 && b == 0; }
};
inline Rgb operator*(double s, const Rgb& c) { return c * s; }
inline Rgb cmin(const Rgb& a, const Rgb& b) { return {std::min(a.r, b.r), std::min(a.g, b.g), std::min(a.b, b.b)}; }
inline Rgb cmax(const Rgb& a, const Rgb& b) { return {std::max(a.r, b.r), std::max(a.g, b.g), std::max(a.b, b.b)}; }
inline bool finite(const Rgb& c) { return std::isfinite(c.r) && std::isfinite(c.g) && std::isfinite(c.b); }

struct Aabb {
    Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
    void grow(const Vec3& p) { lo = vmin(lo, p); hi = vmax(hi, p); }
    void grow(const Aabb& b) { lo = vmin(lo, b.lo); hi = vmax(hi, b.hi); }
    bool empty() const { return lo.x > hi.x; }
    Vec3 center() const { return (lo + hi) * 0.5; }
    Vec3 extent() const { return hi - lo; }
    double diagonal() const { return empty() ? 0.0 : length(hi - lo); }
    // The box moved out by `tol` on every side (a margin for tolerances and lifted ray ends).
    // An empty box stays empty: it holds no point to grow around.
    Aabb grown(double tol) const { return grown(Vec3{tol, tol, tol}); }
    // The box moved out by t[a] on both sides along each axis a; an empty box stays empty.
    Aabb grown(const Vec3& t) const {
        if (empty()) return *this;
        return {lo - t, hi + t};
    }
    // The cube of half-side r about p: on every axis from p - r to p + r.
    static Aabb around(const Vec3& p, double r) {
        const Vec3 t{r, r, r};
        return {p - t, p + t};
    }
    bool contains(const Vec3& p) const {
        return p.x >= lo.x && p.x <= hi.x && p.y >= lo.y && p.y <= hi.y && p.z >= lo.z && p.z <= hi.z;
    }
    // The largest dot(n, p) over the box's points.
    double max_along(const Vec3& n) const {
        double m = 0;
        for (int a = 0; a < 3; ++a) m += std::max(n[a] * lo[a], n[a] * hi[a]);
        return m;
    }
    bool overlaps(const Aabb& b) const {
        for (int a = 0; a < 3; ++a)
            if (b.lo[a] > hi[a] || b.hi[a] < lo[a]) return false;
        return true;
    }
    // The squared distance between the nearest points of this box and b (0 when they meet).
    double distance2(const Aabb& b) const {
        double s = 0;
        for (int a = 0; a < 3; ++a) {
            const double gap = std::max({0.0, b.lo[a] - hi[a], lo[a] - b.hi[a]});
            s += gap * gap;
        }
        return s;
    }
    // The box of the points in both boxes, or none when on some axis the two do not meet
    // (touching counts as meeting: the result is then flat on that axis).
    std::optional<Aabb> intersection(const Aabb& b) const {
        const Aabb m{vmax(lo, b.lo), vmin(hi, b.hi)};
        if (!(m.lo.x <= m.hi.x && m.lo.y <= m.hi.y && m.lo.z <= m.hi.z)) return std::nullopt;
        return m;
    }
    // Does some segment from a point of `a` to a point of `b` pass through this box? Those
    // segments fill the convex hull of a and b, which is the union over t in [0,1] of the
    // boxes (1 - t) a + t b: per axis two conditions linear in t. Exact for that hull.
    bool meets_shaft(const Aabb& a, const Aabb& b) const {
        double t0 = 0, t1 = 1;
        auto keep = [&](double p, double q) {  // p + q t <= 0
            if (q == 0) return p <= 0;
            if (q > 0) t1 = std::min(t1, -p / q);
            else t0 = std::max(t0, -p / q);
            return t0 <= t1;
        };
        for (int k = 0; k < 3; ++k) {
            if (!keep(a.lo[k] - hi[k], b.lo[k] - a.lo[k])) return false;  // the moving box's low side below our high side
            if (!keep(lo[k] - a.hi[k], a.hi[k] - b.hi[k])) return false;  // its high side above our low side
        }
        return true;
    }
    // Does the segment a-b pass through the box (slab test)?
    bool meets_segment(const Vec3& a, const Vec3& b) const {
        double t0 = 0, t1 = 1;
        for (int k = 0; k < 3; ++k) {
            const double d = b[k] - a[k];
            if (d == 0) {
                if (a[k] < lo[k] || a[k] > hi[k]) return false;
                continue;
            }
            double u = (lo[k] - a[k]) / d, v = (hi[k] - a[k]) / d;
            if (u > v) std::swap(u, v);
            t0 = std::max(t0, u);
            t1 = std::min(t1, v);
            if (t0 > t1) return false;
        }
        return true;
    }
};

// How far the farthest point of box b lies in front of the plane through p with normal n
// (<= 0: the whole box is on or behind it).
inline double plane_reach(const Aabb& b, const Vec3& p, const Vec3& n) {
    const Vec3 half = b.extent() * 0.5;
    return dot(b.center() - p, n) + std::fabs(n.x) * half.x + std::fabs(n.y) * half.y + std::fabs(n.z) * half.z;
}

// Whether the segment a-b passes through one of `boxes` (after a move: a ray whose outcome the
// move may have changed).
inline bool meets_any(const std::vector<Aabb>& boxes, const Vec3& a, const Vec3& b) {
    for (const Aabb& box : boxes)
        if (box.meets_segment(a, b)) return true;
    return false;
}

constexpr double kPi = 3.14159265358979323846;

}  // namespace radiosity
