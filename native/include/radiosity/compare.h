// Comparing two solutions (tests and benchmarks: incremental vs full, ours vs a reference).
#pragma once
#include <cmath>
#include <vector>

namespace radiosity {

// Normalised RMS error of x against ref: sqrt(mean((x - ref)^2)) / sqrt(mean(ref^2)); the
// plain RMS when ref is all zero.
inline double nrmse(const std::vector<float>& x, const std::vector<float>& ref) {
    double num = 0, den = 0;
    for (size_t i = 0; i < x.size() && i < ref.size(); ++i) {
        num += double(x[i] - ref[i]) * (x[i] - ref[i]);
        den += double(ref[i]) * ref[i];
    }
    return den > 0 ? std::sqrt(num / den) : std::sqrt(num);
}

}  // namespace radiosity
