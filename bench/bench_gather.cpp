// Gathering benchmark: what a Jacobi sweep costs per link. Solves a built-in scene (default
// settings but the error threshold, as bench_static) --runs times per threshold and prints the
// counts, the "gather" phase per link gathered (Stats::link_sweeps: links x sweeps), the time
// spent building gather plans, and medians of the times. --save writes every threshold's corner
// radiance to a file and --compare reads one back and prints the NRMSE against it, so two builds
// (before and after a gather change) can be checked for equal results.
// Usage: bench_gather [--runs N] [--threads N] [--save FILE | --compare FILE] [box_room|cornell|furnace] [eps ...]
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "radiosity/builtin_scenes.h"
#include "radiosity/compare.h"
#include "radiosity/solver.h"

using namespace radiosity;

namespace {
double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[v.size() / 2];
}
double phase(const Stats& s, const char* name) {
    for (const auto& p : s.phases)
        if (p.first == name) return p.second;
    return 0.0;
}
}  // namespace

int main(int argc, char** argv) {
    int runs = 3, threads = 0;
    std::string name = "box_room", save, compare;
    std::vector<double> eps;
    for (int i = 1; i < argc; ++i) {
        std::string a = argv[i];
        if (a == "--runs" && i + 1 < argc) runs = std::max(1, std::atoi(argv[++i]));
        else if (a == "--threads" && i + 1 < argc) threads = std::atoi(argv[++i]);
        else if (a == "--save" && i + 1 < argc) save = argv[++i];
        else if (a == "--compare" && i + 1 < argc) compare = argv[++i];
        else if (a == "box_room" || a == "cornell" || a == "furnace") name = a;
        else eps.push_back(std::atof(a.c_str()));
    }
    if (eps.empty()) eps = {0.05, 0.02};
    SceneDesc scene = name == "cornell" ? scenes::cornell_box(8)
                      : name == "furnace" ? scenes::furnace_cube(0.5, 1.0, 4)
                                          : scenes::box_room(8);
    std::vector<float> reference;
    if (!compare.empty()) {
        FILE* f = std::fopen(compare.c_str(), "rb");
        if (!f) { std::fprintf(stderr, "cannot read %s\n", compare.c_str()); return 1; }
        float x;
        while (std::fread(&x, sizeof x, 1, f) == 1) reference.push_back(x);
        std::fclose(f);
    }
    FILE* out = save.empty() ? nullptr : std::fopen(save.c_str(), "wb");
    std::printf("scene: %s, %zu input polygons, %d runs (times are medians)\n\n", name.c_str(), scene.polygon_count(), runs);
    std::printf("| eps | elements | links | rays | sweeps | link-sweeps | gather s | gather ns per link-sweep | sweeps ns per "
                "link-sweep | plans | plan s | plan / sweep | closure s | total s |%s\n", compare.empty() ? "" : " NRMSE vs saved |");
    std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|%s\n", compare.empty() ? "" : "---|");
    size_t offset = 0;
    for (double e : eps) {
        Settings st;
        st.error_threshold = e;
        st.threads = threads;
        std::vector<double> gather, per_link, sweep_per_link, plan, plan_per_sweep, closure, total;
        Stats s;
        std::vector<float> corners;
        for (int r = 0; r < runs; ++r) {
            Solver solver(scene, st);
            solver.solve();
            s = solver.stats();
            const double g = phase(s, "gather");
            const double links = double(std::max<int64_t>(1, s.link_sweeps));
            gather.push_back(g);
            per_link.push_back(1e9 * g / links);  // the whole phase: sweeps, plan builds, collecting receivers
            sweep_per_link.push_back(1e9 * s.seconds_sweeps / links);  // the sweeps alone
            plan.push_back(s.seconds_gather_plan);
            // One plan build (the mean over closure and gather builds) against one sweep.
            const double sweep = s.seconds_sweeps / std::max(1, s.iterations);
            const double build = s.seconds_gather_plan / double(std::max<int64_t>(1, s.gather_plans));
            plan_per_sweep.push_back(sweep > 0 ? build / sweep : 0.0);
            closure.push_back(phase(s, "closure"));
            total.push_back(s.seconds_total);
            corners = solver.all_corner_radiance();
        }
        std::printf("| %g | %lld | %lld | %lld | %d | %lld | %.3f | %.1f | %.1f | %lld | %.4f | %.2f | %.3f | %.3f |", e,
                    (long long)s.elements, (long long)s.links, (long long)s.rays, s.iterations, (long long)s.link_sweeps,
                    median(gather), median(per_link), median(sweep_per_link), (long long)s.gather_plans, median(plan),
                    median(plan_per_sweep), median(closure), median(total));
        if (!compare.empty()) {
            std::vector<float> ref;
            if (offset + corners.size() <= reference.size())
                ref.assign(reference.begin() + long(offset), reference.begin() + long(offset + corners.size()));
            if (ref.size() == corners.size()) std::printf(" %.3g |", nrmse(corners, ref));
            else std::printf(" (saved file does not match) |");
        }
        std::printf("\n");
        offset += corners.size();
        if (out) std::fwrite(corners.data(), sizeof(float), corners.size(), out);
    }
    if (out) std::fclose(out);
    return 0;
}
