// Seeded random numbers (Rng), which link evaluation jitters its points by, and the
// stratified cosine-distributed directions (CosineStrata) that hemisphere loops draw from them.
#pragma once
#include <cstdint>

#include "radiosity/geometry.h"

namespace radiosity {

// Counter-based RNG seeded per link so results do not depend on thread scheduling.
class Rng {
public:
    explicit Rng(uint64_t seed) : state_(seed * 0x9E3779B97F4A7C15ull + 0x632BE59BD9B4E019ull) {}
    double next() {  // [0,1)
        uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        z ^= z >> 31;
        return double(z >> 11) * (1.0 / 9007199254740992.0);
    }
private:
    uint64_t state_;
};

// Cosine-distributed directions about the unit vector n, stratified over a side x side grid
// of the unit square: direction i jitters within cell (i % side, i / side), drawing its azimuth
// number, then its polar one, from rng. The order of the draws is fixed here so that every
// hemisphere loop built on this casts the same rays, whatever it does between them (it may
// stop early, or skip directions).
class CosineStrata {
public:
    CosineStrata(const Vec3& n, int side) : n_(n), side_(side) { frame(n, u_, v_); }
    int count() const { return side_ * side_; }
    Vec3 direction(int i, Rng& rng) const {
        const double r1 = (i % side_ + rng.next()) / side_;
        const double r2 = (i / side_ + rng.next()) / side_;
        return cosine_direction(u_, v_, n_, r1, r2);
    }

private:
    Vec3 n_, u_, v_;
    int side_;
};

}  // namespace radiosity
