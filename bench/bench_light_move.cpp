// Light-move benchmark: a point light moved in the scene of the Blender light tests
// (scenes::point_light_box_on_floor), updated incrementally and compared with a full solve of
// the moved scene: NRMSE between them, the update / full time ratio (median over --runs runs,
// both timed in the same run), and the counts behind it (rays cast, links evaluated, elements,
// links). The update's counts are the difference of the solver's running totals.
// Usage: bench_light_move [--quick] [--runs N] [--preset DRAFT|MEDIUM|HIGH] [x y z ...]
//   (destinations of the light; default: the Blender test's move and a few others)
//   --quick (CI smoke run, no timing judged): DRAFT, one run, only the Blender test's move
//   unless destinations are given; options after it override it.
#include <algorithm>
#include <chrono>
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
    return v[v.size() / 2];
}
double seconds_since(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}
}  // namespace

int main(int argc, char** argv) {
    int runs = 3;
    std::string preset = "HIGH";
    std::vector<double> xyz;
    bool quick = false;
    for (int i = 1; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--quick")) quick = true, runs = 1, preset = "DRAFT";
        else if (!std::strcmp(argv[i], "--runs") && i + 1 < argc) runs = std::max(1, std::atoi(argv[++i]));
        else if (!std::strcmp(argv[i], "--preset") && i + 1 < argc) preset = argv[++i];
        else xyz.push_back(std::atof(argv[i]));
    }
    std::vector<Vec3> moves;
    for (size_t i = 0; i + 2 < xyz.size(); i += 3) moves.push_back({xyz[i], xyz[i + 1], xyz[i + 2]});
    if (moves.empty())
        moves = {{0.9, -0.6, 1.3}, {-1.0, 1.0, 1.2}, {1.0, 1.5, 1.0}, {-1.5, -1.5, 2.0}, {0.3, -1.0, 1.0},
                 {1.6, 1.6, 0.6}, {-0.2, 0.3, 1.0}, {-0.4, -0.3, 1.5}};
    if (quick && xyz.empty()) moves.resize(1);
    const Vec3 from{-0.5, -0.3, 1.5};
    const Settings st = Settings::preset(preset);
    std::printf("point light from (%g, %g, %g), preset %s, %d runs (time ratio: median of per-run ratios)\n\n", from.x,
                from.y, from.z, preset.c_str(), runs);
    std::printf("| to | NRMSE inc vs full | time update / full | rays update / full | links evaluated update / full "
                "| elements update / full | links update / full |\n|---|---|---|---|---|---|---|\n");
    std::vector<std::string> phases;  // of the last run, per move
    for (const Vec3& to : moves) {
        std::vector<double> ratio;
        double err = 0;
        Stats su, sf;
        int64_t rays = 0, evaluated = 0;
        for (int r = 0; r < runs; ++r) {
            Solver inc(scenes::point_light_box_on_floor(from), st);
            inc.solve();
            const int64_t rays0 = inc.stats().rays, eval0 = inc.stats().links_evaluated;
            LightDesc moved = inc.scene().lights()[0];
            moved.position = to;
            auto t0 = std::chrono::steady_clock::now();
            inc.set_light(0, moved);
            inc.update();
            const double tu = seconds_since(t0);
            t0 = std::chrono::steady_clock::now();
            Solver full(scenes::point_light_box_on_floor(to), st);
            full.solve();
            const double tf = seconds_since(t0);
            ratio.push_back(tu / tf);
            err = nrmse(inc.all_corner_radiance(), full.all_corner_radiance());
            su = inc.stats();
            sf = full.stats();
            rays = su.rays - rays0;
            evaluated = su.links_evaluated - eval0;
        }
        std::printf("| (%g, %g, %g) | %.3f %% | %.2f | %lld / %lld | %lld / %lld | %lld / %lld | %lld / %lld |\n", to.x, to.y,
                    to.z, 100 * err, median(ratio), (long long)rays, (long long)sf.rays, (long long)evaluated,
                    (long long)sf.links_evaluated, (long long)su.elements, (long long)sf.elements, (long long)su.links,
                    (long long)sf.links);
        char buf[64];
        std::string line = "(" + std::to_string(to.x) + ", " + std::to_string(to.y) + ", " + std::to_string(to.z) + ") update:";
        for (const auto& p : su.phases) std::snprintf(buf, sizeof buf, " %s %.3f", p.first.c_str(), p.second), line += buf;
        line += " | full:";
        for (const auto& p : sf.phases) std::snprintf(buf, sizeof buf, " %s %.3f", p.first.c_str(), p.second), line += buf;
        phases.push_back(line);
    }
    std::printf("\nSeconds per phase (last run):\n");
    for (const std::string& l : phases) std::printf("  %s\n", l.c_str());
    return 0;
}
