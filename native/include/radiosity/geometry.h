// Planar polygons (triangles and quads) of the element quadtrees, their cubature points, and
// the analytic point-to-polygon form factor that every surface link is built on (the seeded
// random numbers that link evaluation jitters its points by are in random.h).
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <random>

#include "radiosity/vec.h"

namespace radiosity {

// A convex planar triangle or quad; vertices wound counter-clockwise about `normal()`.
struct Poly {
    std::array<Vec3, 4> v{};
    int n = 3;

    Vec3 centroid() const;   // area centroid
    Vec3 normal() const;     // unit; zero for a degenerate polygon
    double area() const;
    // Child k of a quadtree split; child k (k < n) holds corner k of the parent, so the
    // leaf at an input corner is found by always descending into the same child index.
    Poly child(int k) const;
    // Uniformly distributed point for (u1,u2) in [0,1)^2.
    Vec3 sample(double u1, double u2) const { return sample(first_share(), u1, u2); }
    // The same with a quad's first_share() computed once (samplers draw many points).
    Vec3 sample(double share, double u1, double u2) const;
    // Quads: the share of the area in triangle (v0, v1, v2); 1 for a triangle.
    double first_share() const;
};

// The part of a polygon in front of a plane, as up to four triangles, sampled uniformly:
// visibility rays toward a point go only where the point's kernel is non-zero. A quad is the
// two triangles (v0, v1, v2) and (v0, v2, v3), as Poly::area and Poly::sample read it. A
// planar convex quad (to 1e-9) is clipped whole, a fan of up to three triangles; a warped or
// concave one the plane cuts is clipped one triangle at a time (two pieces of at most four
// vertices): the hierarchy keeps quads planar only to 1e-4 of their size, and a plane nearly
// containing such a quad crosses it four times.
struct FrontPart {
    std::array<std::array<Vec3, 3>, 4> tri{};
    std::array<double, 4> tri_area{};
    int n = 0;          // triangles; 0 when nothing of the polygon lies in front
    double area = 0;
    Vec3 sample(double u1, double u2) const;
};
// The part of `poly` where dot(p - x, nx) > 0. Any input is safe: a non-finite x or nx, or a
// degenerate polygon, gives n = 0.
FrontPart front_part(const Poly& poly, const Vec3& x, const Vec3& nx);

// How far x (a point in the polygon's plane) lies outside `poly`, whose unit normal is n: the
// largest distance beyond one of its edges, 0 inside.
double distance_outside(const Poly& poly, const Vec3& n, const Vec3& x);
// Distance from x to a box (0 inside).
double distance_to_box(const Aabb& b, const Vec3& x);
// Whether x (a point in the polygon's plane) lies inside `poly` (unit normal n) or at most
// `tol` beyond any of its edges.
bool within_edges(const Poly& poly, const Vec3& n, const Vec3& x, double tol);

// Receiver cubature: points and weights (summing to 1) over the polygon.
struct Cubature {
    std::array<Vec3, 4> p{};
    std::array<double, 4> w{};
    int n = 0;
};
Cubature cubature(const Poly& poly);
// Cubature of the receiver `rcv` for the kernel of a sender in plane (src_p, src_n): where the
// receiver straddles that plane, only its part in front of it, with weights summing to that
// part's share of the area (the rest sees the sender's back: kernel 0). The plain rule can put
// every point behind (a floor patch under a box sees the box's side only beyond its foot):
// the coupling would come out 0 and the pair be dropped, however large its front part.
Cubature receiver_cubature(const Poly& rcv, const Vec3& src_p, const Vec3& src_n);

// Differential-area-to-polygon form factor from point x with unit normal nx to `poly`
// (unoccluded), i.e. the fraction of the light leaving x that reaches poly. Only the part of
// the polygon above x's tangent plane counts, and only if x is in front of the polygon
// (the polygon's front side emits toward x). Exact (Lambert's contour formula).
double point_polygon_form_factor(const Vec3& x, const Vec3& nx, const Poly& poly, const Vec3& poly_normal);
// The same for a convex planar polygon of n <= 12 vertices (a clipped element).
double point_polygon_form_factor(const Vec3& x, const Vec3& nx, const Vec3* v, int n, const Vec3& poly_normal);

// How far a quad's vertices lie off the plane through their mean with normal n (0 for a
// triangle): the hierarchy keeps quads planar to 1e-4 of their size, not exactly.
double warp(const Poly& p, const Vec3& n);
// Whether any transfer from `src` (front side) to `rcv` (front side) is geometrically possible:
// each has a vertex in front of the other's plane by more than eps plus both warps.
bool can_face(const Poly& src, const Vec3& src_n, const Poly& rcv, const Vec3& rcv_n, double eps);

// An orthonormal frame (u, v, w) around the unit vector w.
inline void frame(const Vec3& w, Vec3& u, Vec3& v) {
    const Vec3 t = std::fabs(w.x) > 0.5 ? Vec3{0, 1, 0} : Vec3{1, 0, 0};
    u = normalize(cross(w, t));
    v = cross(w, u);
}

// The cosine-distributed direction about w (frame u, v, w) for (r1, r2) in [0, 1)^2: azimuth
// 2 pi r1, sine of the polar angle sqrt(r2).
inline Vec3 cosine_direction(const Vec3& u, const Vec3& v, const Vec3& w, double r1, double r2) {
    const double phi = 2 * kPi * r1, sr = std::sqrt(r2);
    return u * (std::cos(phi) * sr) + v * (std::sin(phi) * sr) + w * std::sqrt(1 - r2);
}

// The numbers (r1, r2) of cosine_direction about n (frame nu, nv, n) whose rays, from any
// origin in the ball (c, r), may meet `box`: a superset, found from the cone toward the box's
// bounding ball (what a replay after a move must cast again of a uniform sky's samples).
class CosineWindow {
public:
    CosineWindow() = default;  // every sample
    CosineWindow(const Aabb& box, const Vec3& c, double r, const Vec3& nu, const Vec3& nv, const Vec3& n);
    bool may_meet(double r1, double r2) const {
        if (all_) return true;
        if (none_ || r2 < r2_lo_ || r2 > r2_hi_) return false;
        if (r1_half_ >= 0.5) return true;
        const double d = std::fabs(r1 - r1_mid_);
        return std::min(d, 1 - d) <= r1_half_;
    }

private:
    bool all_ = true, none_ = false;
    double r2_lo_ = 0, r2_hi_ = 1, r1_mid_ = 0, r1_half_ = 0.5;
};

}  // namespace radiosity
