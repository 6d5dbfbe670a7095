// Equirectangular world map (environment.h): lookup and importance sampling by luminance x
// solid angle, texels constant over their patch of the sphere.
#include "radiosity/environment.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace radiosity {

namespace {
// Latitude of the top edge of row i (row 0 at the top, +Z).
double row_lat(int i, int h) { return kPi * (0.5 - double(i) / h); }
}  // namespace

EnvMap::EnvMap(int width, int height, std::vector<Rgb> texels)
    : w_(width), h_(height), texels_(std::move(texels)) {
    if (w_ < 1 || h_ < 1 || texels_.size() != size_t(w_) * size_t(h_))
        throw std::invalid_argument("environment map: size does not match its texels");
    for (const Rgb& t : texels_)
        if (!finite(t) || t.r < 0 || t.g < 0 || t.b < 0)
            throw std::invalid_argument("environment map: negative or non-finite radiance");
    weight_.assign(texels_.size(), 0.0);
    row_cdf_.assign(size_t(h_) + 1, 0.0);
    col_cdf_.assign(size_t(h_) * (size_t(w_) + 1), 0.0);
    Rgb flux;
    for (int i = 0; i < h_; ++i) {
        const double omega = 2 * kPi / w_ * (std::sin(row_lat(i, h_)) - std::sin(row_lat(i + 1, h_)));
        double* cdf = &col_cdf_[size_t(i) * (w_ + 1)];
        for (int j = 0; j < w_; ++j) {
            const Rgb& t = texels_[size_t(i) * w_ + j];
            weight_[size_t(i) * w_ + j] = t.mean() * omega;
            cdf[j + 1] = cdf[j] + t.mean() * omega;
            flux += t * omega;
        }
        row_cdf_[i + 1] = row_cdf_[i] + cdf[w_];
    }
    total_ = row_cdf_[h_];
    mean_ = flux / (4 * kPi);
    // Coarse blocks for irradiance(): at most 32 x 16 of them.
    const int bw = std::min(w_, 32), bh = std::min(h_, 16);
    blocks_.assign(size_t(bw) * bh, {Vec3{}, Vec3{}, Vec3{}});
    for (int i = 0; i < h_; ++i) {
        const double a = row_lat(i + 1, h_), b = row_lat(i, h_);
        // Integrals over the texel's latitude band of cos^2 (x, y) and sin cos (z).
        const double c2 = 0.5 * (b - a) + 0.25 * (std::sin(2 * b) - std::sin(2 * a));
        const double sc = 0.5 * (std::sin(b) * std::sin(b) - std::sin(a) * std::sin(a));
        for (int j = 0; j < w_; ++j) {
            const double p1 = kPi * (1 - 2.0 * j / w_), p0 = kPi * (1 - 2.0 * (j + 1) / w_);  // phi range
            const Vec3 D{(std::sin(p1) - std::sin(p0)) * c2, (std::cos(p0) - std::cos(p1)) * c2, (p1 - p0) * sc};
            const Rgb& t = texels_[size_t(i) * w_ + j];
            auto& blk = blocks_[size_t(i * bh / h_) * bw + size_t(j * bw / w_)];
            for (int k = 0; k < 3; ++k) blk[k] += D * t[k];
        }
    }
}

Rgb EnvMap::irradiance(const Vec3& n) const {
    Rgb e;
    for (const auto& blk : blocks_)
        for (int k = 0; k < 3; ++k) e[k] += std::max(0.0, dot(n, blk[k]));
    return e;
}

Vec3 EnvMap::direction(double u, double v) {
    const double phi = kPi * (1 - 2 * u), lat = kPi * (v - 0.5);
    const double c = std::cos(lat);
    return {std::cos(phi) * c, std::sin(phi) * c, std::sin(lat)};
}

int EnvMap::texel(const Vec3& d) const {
    const double u = 0.5 - std::atan2(d.y, d.x) / (2 * kPi);
    const double v = std::atan2(d.z, std::hypot(d.x, d.y)) / kPi + 0.5;
    const int j = std::clamp(int(std::floor(u * w_)), 0, w_ - 1);
    const int i = std::clamp(int(std::floor((1 - v) * h_)), 0, h_ - 1);
    return i * w_ + j;
}

Rgb EnvMap::radiance(const Vec3& d) const { return texels_[size_t(texel(d))]; }

double EnvMap::pdf(const Vec3& d) const {
    if (total_ <= 0) return 0;
    const int t = texel(d);
    const double w = weight_[size_t(t)];
    // weight / total is the texel's probability; spread uniformly over its solid angle.
    return w > 0 ? texels_[size_t(t)].mean() / total_ : 0.0;
}

Vec3 EnvMap::sample(double a, double b, double& pdf) const {
    pdf = 0;
    if (total_ <= 0) return {0, 0, 1};
    // Row, then column within it; the leftover of each uniform number places the point inside.
    const double ta = a * total_;
    int i = int(std::upper_bound(row_cdf_.begin(), row_cdf_.end(), ta) - row_cdf_.begin()) - 1;
    i = std::clamp(i, 0, h_ - 1);
    while (i > 0 && row_cdf_[i + 1] - row_cdf_[i] <= 0) --i;  // a = 1 - eps past an empty tail
    const double rw = row_cdf_[i + 1] - row_cdf_[i];
    const double fa = rw > 0 ? std::clamp((ta - row_cdf_[i]) / rw, 0.0, 1.0) : 0.5;
    const double* cdf = &col_cdf_[size_t(i) * (w_ + 1)];
    const double tb = b * cdf[w_];
    int j = int(std::upper_bound(cdf, cdf + w_ + 1, tb) - cdf) - 1;
    j = std::clamp(j, 0, w_ - 1);
    while (j > 0 && cdf[j + 1] - cdf[j] <= 0) --j;
    // Uniform in solid angle inside the texel: uniform in u and in sin(lat).
    const double u = (j + fa) / w_;
    const double s_hi = std::sin(row_lat(i, h_)), s_lo = std::sin(row_lat(i + 1, h_));
    const double s = s_lo + (s_hi - s_lo) * ((tb - cdf[j]) / std::max(cdf[j + 1] - cdf[j], 1e-300));
    const double lat = std::asin(std::clamp(s, -1.0, 1.0));
    const Vec3 d = direction(u, lat / kPi + 0.5);
    pdf = texels_[size_t(i) * w_ + j].mean() / total_;
    return d;
}

}  // namespace radiosity
