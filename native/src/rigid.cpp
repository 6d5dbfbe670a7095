// Rigid::from_world: a Blender world matrix checked and carried into the solver's internal frame.
#include "radiosity/rigid.h"

#include <algorithm>
#include <cmath>

#include "radiosity/scene.h"

namespace radiosity {

Rigid Rigid::from_world(const std::array<double, 16>& m, const Vec3& origin, double unit, const std::string& what) {
    for (int i = 0; i < 16; ++i)
        if (!std::isfinite(m[i])) throw InputError(what + ": the matrix has a NaN or inf entry");
    if (std::fabs(m[12]) > 1e-9 || std::fabs(m[13]) > 1e-9 || std::fabs(m[14]) > 1e-9 || std::fabs(m[15] - 1) > 1e-9)
        throw InputError(what + ": the matrix is not affine (last row must be 0 0 0 1)");
    double R[9] = {m[0], m[1], m[2], m[4], m[5], m[6], m[8], m[9], m[10]};
    // Rigid only: R^T R = I and det R = +1 (the paper's moves are translations and rotations).
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            double d = R[i] * R[j] + R[3 + i] * R[3 + j] + R[6 + i] * R[6 + j];
            if (std::fabs(d - (i == j ? 1.0 : 0.0)) > 1e-5)
                throw InputError(what +
                                 ": the move is not rigid (scale or shear); apply the scale to the mesh and bake in full");
        }
    double det = R[0] * (R[4] * R[8] - R[5] * R[7]) - R[1] * (R[3] * R[8] - R[5] * R[6]) + R[2] * (R[3] * R[7] - R[4] * R[6]);
    if (det < 0) throw InputError(what + ": the move mirrors the object; bake in full");
    // World p = R p0 + m_t; internal p_i = (p - o) / u, so p_i = R p0_i + (R o + m_t - o) / u.
    const Vec3 mt{m[3], m[7], m[11]};
    Rigid p;
    std::copy(R, R + 9, p.R.begin());
    p.t = (p.dir(origin) + mt - origin) / unit;
    // Beyond 1e12 scene diagonals rays to it leave float range, and Embree refuses them.
    for (int k = 0; k < 3; ++k)
        if (!(std::fabs(p.t[k]) <= 1e12)) throw InputError(what + ": the move takes it more than 1e12 scene sizes away");
    return p;
}

}  // namespace radiosity
