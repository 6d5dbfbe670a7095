// A rigid placement, p -> R p + t (R a rotation, row-major): where an object stands relative to
// where its geometry was given, in the solver's internal frame. The one type for placements:
// moves, the live preview's carry from the solved placement to the dragged one, and Embree's
// instance transforms. Made from a Blender world matrix by from_world, which checks that it is
// rigid; nothing else here checks it.
#pragma once
#include <array>
#include <string>

#include "radiosity/vec.h"

namespace radiosity {

struct Rigid {
    std::array<double, 9> R{1, 0, 0, 0, 1, 0, 0, 0, 1};
    Vec3 t;

    // A direction turned by R (no translation).
    Vec3 dir(const Vec3& v) const {
        return {R[0] * v.x + R[1] * v.y + R[2] * v.z, R[3] * v.x + R[4] * v.y + R[5] * v.z,
                R[6] * v.x + R[7] * v.y + R[8] * v.z};
    }
    Vec3 point(const Vec3& p) const {
        return {R[0] * p.x + R[1] * p.y + R[2] * p.z + t.x, R[3] * p.x + R[4] * p.y + R[5] * p.z + t.y,
                R[6] * p.x + R[7] * p.y + R[8] * p.z + t.z};
    }
    // The placement that takes geometry placed by `from` to this placement: (R R_from^T,
    // t - R R_from^T t_from).
    Rigid relative_to(const Rigid& from) const {
        Rigid c;
        for (int r = 0; r < 3; ++r)
            for (int k = 0; k < 3; ++k)
                c.R[size_t(3 * r + k)] = R[size_t(3 * r)] * from.R[size_t(3 * k)] +
                                         R[size_t(3 * r + 1)] * from.R[size_t(3 * k + 1)] +
                                         R[size_t(3 * r + 2)] * from.R[size_t(3 * k + 2)];
        c.t = t - c.dir(from.t);
        return c;
    }
    // A Blender world matrix m (row-major 4 x 4: world p = R p0 + t) as the placement in the
    // internal frame whose world points are origin + unit * p. Throws InputError (scene.h),
    // its message opening with `what` (e.g. "object 'Box'"), unless m is finite, affine and
    // rigid (a rotation, no scale, shear or mirroring) and its translation within 1e12 scene sizes.
    static Rigid from_world(const std::array<double, 16>& m, const Vec3& origin, double unit, const std::string& what);
    // Row-major 3 x 4, [R | t] (Embree's instance transform).
    std::array<double, 12> rows() const {
        return {R[0], R[1], R[2], t.x, R[3], R[4], R[5], t.y, R[6], R[7], R[8], t.z};
    }
    bool identity() const { return *this == Rigid{}; }
    bool operator==(const Rigid& o) const { return R == o.R && t.x == o.t.x && t.y == o.t.y && t.z == o.t.z; }
    bool operator!=(const Rigid& o) const { return !(*this == o); }
};

}  // namespace radiosity
