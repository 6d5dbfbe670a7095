// The world as Cycles renders it: an equirectangular radiance map the Sky light reads instead
// of its uniform radiance, sampled in proportion to luminance x solid angle (a sun or a bright
// window in an HDRI is where the light comes from, so that is where the rays go).
//
// Convention (Blender's Environment Texture, world +Z up): texel (row i, column j) of a W x H map
// covers u in [j/W, (j+1)/W), v in [1 - (i+1)/H, 1 - i/H) (row 0 is the top, +Z), and
//     u = 1/2 - atan2(d.y, d.x) / (2 pi),   v = 1/2 + atan2(d.z, hypot(d.x, d.y)) / pi,
// i.e. the direction of (u, v) is (cos phi cos lat, sin phi cos lat, sin lat) with
// phi = pi (1 - 2u), lat = pi (v - 1/2): the image's centre looks along +X, u grows clockwise
// seen from above (checked against Blender's Environment Texture: tests/blender/test_textures_world.py). Each texel holds the mean radiance over its patch of
// directions (energy-preserving), constant across it.
#pragma once
#include <array>
#include <vector>

#include "radiosity/vec.h"

namespace radiosity {

class EnvMap {
public:
    // Throws std::invalid_argument for a size that does not match, or a negative / non-finite texel.
    EnvMap(int width, int height, std::vector<Rgb> texels);

    int width() const { return w_; }
    int height() const { return h_; }
    const std::vector<Rgb>& texels() const { return texels_; }

    Rgb radiance(const Vec3& dir) const;  // dir need not be unit
    // Direction drawn with density pdf(d) (per steradian) from two uniform numbers in [0, 1).
    Vec3 sample(double a, double b, double& pdf) const;
    double pdf(const Vec3& dir) const;
    // Irradiance on a surface of unit normal n with nothing in the way: the integral of
    // radiance x max(0, n.d). Exact for texels wholly above or below the surface's horizon
    // (each coarse block of texels keeps its radiance-weighted vector solid angle, so a sun
    // anywhere inside a block keeps its own direction); a block the horizon cuts counts as
    // if it were all on the side of its vector.
    Rgb irradiance(const Vec3& n) const;
    // Integral of radiance over the sphere / 4 pi (per channel).
    Rgb mean() const { return mean_; }
    bool empty_of_light() const { return total_ <= 0; }

    static Vec3 direction(double u, double v);

private:
    int w_, h_;
    std::vector<Rgb> texels_;
    std::vector<double> row_cdf_;  // h_ + 1: rows by weight
    std::vector<double> col_cdf_;  // h_ x (w_ + 1): columns within each row
    std::vector<double> weight_;   // per texel: luminance x solid angle
    double total_ = 0;
    Rgb mean_;
    std::vector<std::array<Vec3, 3>> blocks_;  // per coarse block, per channel: sum of L x (integral of d dw)
    int texel(const Vec3& dir) const;
};

}  // namespace radiosity
