#include "radiosity/geometry.h"

#include <algorithm>
#include <cmath>

namespace radiosity {

namespace {
double tri_area(const Vec3& a, const Vec3& b, const Vec3& c) { return 0.5 * length(cross(b - a, c - a)); }
}  // namespace

double Poly::area() const {
    if (n == 3) return tri_area(v[0], v[1], v[2]);
    return tri_area(v[0], v[1], v[2]) + tri_area(v[0], v[2], v[3]);
}

Vec3 Poly::normal() const {
    // Newell's method: robust for slightly non-planar quads.
    Vec3 nrm;
    for (int i = 0; i < n; ++i) {
        const Vec3& a = v[i];
        const Vec3& b = v[(i + 1) % n];
        nrm.x += (a.y - b.y) * (a.z + b.z);
        nrm.y += (a.z - b.z) * (a.x + b.x);
        nrm.z += (a.x - b.x) * (a.y + b.y);
    }
    return normalize(nrm);
}

Vec3 Poly::centroid() const {
    if (n == 3) return (v[0] + v[1] + v[2]) / 3.0;
    double a1 = tri_area(v[0], v[1], v[2]), a2 = tri_area(v[0], v[2], v[3]);
    Vec3 c1 = (v[0] + v[1] + v[2]) / 3.0, c2 = (v[0] + v[2] + v[3]) / 3.0;
    double a = a1 + a2;
    return a > 0 ? (c1 * a1 + c2 * a2) / a : (v[0] + v[1] + v[2] + v[3]) / 4.0;
}

Poly Poly::child(int k) const {
    Poly c;
    c.n = n;
    if (n == 3) {
        Vec3 m01 = (v[0] + v[1]) * 0.5, m12 = (v[1] + v[2]) * 0.5, m20 = (v[2] + v[0]) * 0.5;
        switch (k) {
            case 0: c.v = {v[0], m01, m20, Vec3{}}; break;
            case 1: c.v = {m01, v[1], m12, Vec3{}}; break;
            case 2: c.v = {m20, m12, v[2], Vec3{}}; break;
            default: c.v = {m12, m20, m01, Vec3{}}; break;  // the middle one, same winding
            // Each corner child keeps parent corner k at position k (corner lookup relies on it).
        }
        return c;
    }
    Vec3 m[4], ctr = (v[0] + v[1] + v[2] + v[3]) * 0.25;
    for (int i = 0; i < 4; ++i) m[i] = (v[i] + v[(i + 1) % 4]) * 0.5;
    // Child k: corner v[k], edge midpoints around it, the centre; keeps winding and puts
    // v[k] at position k.
    std::array<Vec3, 4> q;
    q[k] = v[k];
    q[(k + 1) % 4] = m[k];
    q[(k + 2) % 4] = ctr;
    q[(k + 3) % 4] = m[(k + 3) % 4];
    c.v = q;
    return c;
}

double Poly::first_share() const {
    if (n == 3) return 1.0;
    double a1 = tri_area(v[0], v[1], v[2]), a2 = tri_area(v[0], v[2], v[3]);
    return (a1 + a2) > 0 ? a1 / (a1 + a2) : 0.5;
}

Vec3 Poly::sample(double f, double u1, double u2) const {
    auto in_tri = [](const Vec3& a, const Vec3& b, const Vec3& c, double s, double t) {
        double su = std::sqrt(s);
        return a * (1 - su) + b * (su * (1 - t)) + c * (su * t);
    };
    if (n == 3) return in_tri(v[0], v[1], v[2], u1, u2);
    if (u1 < f) return in_tri(v[0], v[1], v[2], u1 / f, u2);
    return in_tri(v[0], v[2], v[3], (u1 - f) / (1 - f), u2);
}

namespace {
// Clips the convex polygon v[0..n) (signed distances d), crossed at most twice, at d > 0 into
// out (at most n + 1 vertices); returns the count.
int clip_at_plane(const Vec3* v, const double* d, int n, Vec3* out) {
    int m = 0;
    for (int i = 0; i < n; ++i) {
        const int j = (i + 1) % n;
        if (d[i] > 0) out[m++] = v[i];
        if ((d[i] > 0) != (d[j] > 0)) out[m++] = v[i] + (v[j] - v[i]) * (d[i] / (d[i] - d[j]));
    }
    return m;
}

// Whether a quad is planar (its corners' turns parallel to 1e-9) and convex: a plane then
// crosses it at most twice and it can be clipped whole.
bool planar_convex(const Poly& p) {
    Vec3 c[4];
    for (int k = 0; k < 4; ++k)
        c[k] = cross(p.v[size_t((k + 1) % 4)] - p.v[size_t(k)], p.v[size_t((k + 2) % 4)] - p.v[size_t((k + 1) % 4)]);
    for (int k = 1; k < 4; ++k)
        if (!(dot(c[k], c[0]) > 0) || length(cross(c[k], c[0])) > 1e-9 * length(c[k]) * length(c[0])) return false;
    return true;
}

// Appends the fan of c[0..m) from c[0] to f (nothing when m < 3).
void add_fan(FrontPart& f, const Vec3* c, int m) {
    for (int i = 1; i + 1 < m && f.n < int(f.tri.size()); ++i) {
        const double a = tri_area(c[0], c[i], c[i + 1]);
        f.tri[size_t(f.n)] = {c[0], c[i], c[i + 1]};
        f.tri_area[size_t(f.n)] = a;
        f.area += a;
        ++f.n;
    }
}
}  // namespace

FrontPart front_part(const Poly& poly, const Vec3& x, const Vec3& nx) {
    FrontPart f;
    const int n = poly.n;
    if (n < 3 || n > 4) return f;
    double d[4];
    int crossings = 0;
    for (int i = 0; i < n; ++i) d[i] = dot(poly.v[size_t(i)] - x, nx);
    for (int i = 0; i < n; ++i) crossings += (d[i] > 0) != (d[(i + 1) % n] > 0);
    Vec3 c[5];
    if (n == 3 || crossings == 0 || (crossings == 2 && planar_convex(poly))) {
        add_fan(f, c, clip_at_plane(poly.v.data(), d, n, c));
    } else {
        // A warped or concave quad the plane cuts: its two triangles one by one (its clip as
        // one polygon would leave its surface, and overflow where the plane crosses it four
        // times).
        const int halves[2][3] = {{0, 1, 2}, {0, 2, 3}};
        for (const auto& t : halves) {
            const Vec3 tv[3] = {poly.v[size_t(t[0])], poly.v[size_t(t[1])], poly.v[size_t(t[2])]};
            const double td[3] = {d[t[0]], d[t[1]], d[t[2]]};
            add_fan(f, c, clip_at_plane(tv, td, 3, c));
        }
    }
    if (!(f.area > 0)) {
        f.n = 0;
        f.area = 0;
    }
    return f;
}

Vec3 FrontPart::sample(double u1, double u2) const {
    // u1 picks the triangle by area and is reused within it (stratification along u1 carries
    // over).
    double acc = 0;
    for (int i = 0; i < n; ++i) {
        const double a = tri_area[size_t(i)];
        if (u1 * area <= acc + a || i + 1 == n) {
            const double s = a > 0 ? std::min(1.0, std::max(0.0, (u1 * area - acc) / a)) : 0.5;
            const double su = std::sqrt(s);
            const auto& t = tri[size_t(i)];
            return t[0] * (1 - su) + t[1] * (su * (1 - u2)) + t[2] * (su * u2);
        }
        acc += a;
    }
    return tri[0][0];
}

Cubature cubature(const Poly& p) {
    Cubature c;
    if (p.n == 3) {
        // Degree-2 rule with interior points (weights 1/3): never on an edge, where a
        // neighbour's kernel is singular.
        const double a = 2.0 / 3.0, b = 1.0 / 6.0;
        c.n = 3;
        c.p[0] = p.v[0] * a + p.v[1] * b + p.v[2] * b;
        c.p[1] = p.v[0] * b + p.v[1] * a + p.v[2] * b;
        c.p[2] = p.v[0] * b + p.v[1] * b + p.v[2] * a;
        c.w = {1.0 / 3, 1.0 / 3, 1.0 / 3, 0};
        return c;
    }
    // 2x2 Gauss-Legendre in the bilinear parameterisation, weighted by the Jacobian.
    const double g[2] = {0.5 - 0.5 / std::sqrt(3.0), 0.5 + 0.5 / std::sqrt(3.0)};
    double wsum = 0;
    c.n = 4;
    for (int i = 0; i < 2; ++i)
        for (int j = 0; j < 2; ++j) {
            double s = g[i], t = g[j];
            Vec3 pt = p.v[0] * ((1 - s) * (1 - t)) + p.v[1] * (s * (1 - t)) + p.v[2] * (s * t) + p.v[3] * ((1 - s) * t);
            Vec3 ds = (p.v[1] - p.v[0]) * (1 - t) + (p.v[2] - p.v[3]) * t;
            Vec3 dt = (p.v[3] - p.v[0]) * (1 - s) + (p.v[2] - p.v[1]) * s;
            double jac = length(cross(ds, dt));
            int k = i * 2 + j;
            c.p[k] = pt;
            c.w[k] = jac;
            wsum += jac;
        }
    for (int k = 0; k < 4; ++k) c.w[k] = wsum > 0 ? c.w[k] / wsum : 0.25;
    return c;
}

double point_polygon_form_factor(const Vec3& x, const Vec3& nx, const Poly& poly, const Vec3& pn) {
    return point_polygon_form_factor(x, nx, poly.v.data(), poly.n, pn);
}

double point_polygon_form_factor(const Vec3& x, const Vec3& nx, const Vec3* v, int n, const Vec3& pn) {
    if (n < 3 || n > 12) return 0.0;
    // The receiving point must lie in front of the emitting side.
    if (dot(x - v[0], pn) <= 0) return 0.0;
    // Clip the polygon to the half-space above x's tangent plane (a polygon that straddles it
    // would otherwise contribute a negative part).
    Vec3 pts[24];
    int m = 0;
    const double h_eps = 1e-12;
    for (int i = 0; i < n; ++i) {
        const Vec3& a = v[i];
        const Vec3& b = v[(i + 1) % n];
        double da = dot(a - x, nx), db = dot(b - x, nx);
        bool ina = da > h_eps, inb = db > h_eps;
        if (ina) pts[m++] = a;
        if (ina != inb) {
            double t = (da - h_eps) / (da - db);
            pts[m++] = a + (b - a) * t;
        }
    }
    if (m < 3) return 0.0;
    // Lambert: F = 1/(2 pi) * sum_i angle_i * (n . unit(r_i x r_{i+1})).
    double sum = 0;
    for (int i = 0; i < m; ++i) {
        Vec3 r1 = pts[i] - x, r2 = pts[(i + 1) % m] - x;
        Vec3 c = cross(r1, r2);
        double cl = length(c);
        if (cl <= 0) continue;
        double ang = std::atan2(cl, dot(r1, r2));
        sum += ang * dot(nx, c) / cl;
    }
    return std::fabs(sum) / (2.0 * kPi);
}

double distance_to_box(const Aabb& b, const Vec3& x) {
    double d2 = 0;
    for (int a = 0; a < 3; ++a) {
        const double o = std::max({b.lo[a] - x[a], 0.0, x[a] - b.hi[a]});
        d2 += o * o;
    }
    return std::sqrt(d2);
}

double distance_outside(const Poly& poly, const Vec3& n, const Vec3& x) {
    double o = 0;
    for (int k = 0; k < poly.n; ++k) {
        Vec3 e = poly.v[(k + 1) % poly.n] - poly.v[k];
        o = std::max(o, -dot(cross(e, x - poly.v[k]), n));
    }
    return o;
}

bool within_edges(const Poly& poly, const Vec3& n, const Vec3& x, double tol) {
    for (int k = 0; k < poly.n; ++k) {
        const Vec3 e = poly.v[(k + 1) % poly.n] - poly.v[k];
        if (dot(cross(e, x - poly.v[k]), n) < -tol * length(e)) return false;
    }
    return true;
}

Cubature receiver_cubature(const Poly& rcv, const Vec3& src_p, const Vec3& src_n) {
    const FrontPart f = front_part(rcv, src_p, src_n);
    const double area = rcv.area();
    if (f.n == 0 || !(area > 0) || f.area >= (1.0 - 1e-9) * area) return cubature(rcv);
    // The front part's triangles (up to four), each by its centroid (exact for a linear
    // kernel; the oracle refines where the kernel varies more, as the spread at the corners,
    // 0 behind, tells it).
    Cubature c;
    for (int i = 0; i < f.n; ++i) {
        const double a = f.tri_area[size_t(i)];
        if (!(a > 0)) continue;
        const auto& t = f.tri[size_t(i)];
        c.p[size_t(c.n)] = (t[0] + t[1] + t[2]) * (1.0 / 3.0);
        c.w[size_t(c.n)] = a / area;
        ++c.n;
    }
    if (c.n == 0) return cubature(rcv);
    return c;
}

namespace {
// A point of the polygon's plane to measure from: a quad's vertex mean (the plane that halves
// its warp), a triangle's first vertex.
Vec3 plane_point(const Poly& p) { return p.n == 4 ? (p.v[0] + p.v[1] + p.v[2] + p.v[3]) * 0.25 : p.v[0]; }
}  // namespace

double warp(const Poly& p, const Vec3& n) {
    if (p.n < 4) return 0;
    const Vec3 c = plane_point(p);
    double w = 0;
    for (int i = 0; i < 4; ++i) w = std::max(w, std::fabs(dot(p.v[size_t(i)] - c, n)));
    return w;
}

bool can_face(const Poly& src, const Vec3& src_n, const Poly& rcv, const Vec3& rcv_n, double eps) {
    // Some point of the receiver must be in front of the sender and vice versa, by more than
    // the two polygons' warps: within them, the two are one sheet (the far side of a warped
    // quad is a hair "in front" of its own vertices) and exchange no light.
    const double tol = eps + warp(src, src_n) + warp(rcv, rcv_n);
    const Vec3 sc = plane_point(src), rc = plane_point(rcv);
    bool rcv_front = false, src_front = false;
    for (int i = 0; i < rcv.n; ++i)
        if (dot(rcv.v[size_t(i)] - sc, src_n) > tol) rcv_front = true;
    for (int i = 0; i < src.n; ++i)
        if (dot(src.v[size_t(i)] - rc, rcv_n) > tol) src_front = true;
    return rcv_front && src_front;
}

CosineWindow::CosineWindow(const Aabb& box, const Vec3& c, double r, const Vec3& nu, const Vec3& nv, const Vec3& n) {
    all_ = false;
    if (box.empty()) {  // nothing to meet
        none_ = true;
        return;
    }
    const Vec3 v = box.center() - c;
    const double L = length(v);
    // (A margin far above the rounding of a sample's direction and of a segment's box test.)
    const double R = (0.5 * box.diagonal() + r) * (1 + 1e-6) + 1e-12 * L;
    if (!(L > R)) {  // the origins reach into the ball: every direction
        all_ = true;
        return;
    }
    // Directions within alpha of the axis toward the ball's centre: polar angles th0 +- alpha,
    // and, when no pole lies inside, azimuths within asin(sin alpha / sin th0) of the axis'.
    const double alpha = std::asin(R / L), th0 = std::acos(std::clamp(dot(v, n) / L, -1.0, 1.0));
    const double lo = th0 - alpha, hi = th0 + alpha, quarter = 0.5 * kPi, eps = 1e-9;
    if (lo >= quarter) {  // wholly below the horizon
        none_ = true;
        return;
    }
    r2_lo_ = lo <= 0 ? 0.0 : std::sin(lo) * std::sin(lo) - eps;
    r2_hi_ = hi >= quarter ? 1.0 : std::sin(hi) * std::sin(hi) + eps;
    const double s = std::sin(alpha) / std::sin(th0);
    if (lo <= 0 || hi >= kPi || s >= 1) return;  // every azimuth
    r1_half_ = std::asin(s) / (2 * kPi) + eps;
    r1_mid_ = std::atan2(dot(v, nv), dot(v, nu)) / (2 * kPi);
    if (r1_mid_ < 0) r1_mid_ += 1;
}

}  // namespace radiosity
