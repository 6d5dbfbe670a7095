// Gathering benchmark: what a Jacobi sweep costs per link. Solves a built-in scene (default
// settings but the error threshold, as bench_static) --runs times per threshold and prints the
// counts, the "gather" phase per link gathered (Stats::link_sweeps: links x sweeps), the time
// spent building gather plans, and medians of the times. --save writes every threshold's corner
// radiance to a file and --compare reads one back and prints the NRMSE against it, so two builds
// (before and after a gather change) can be checked for equal results.
// --micro: after each solve, builds a GatherPlan from the solver's final hierarchy and links and
// times a plan build, its radiometric part, a unit sweep (with the plan and straight from the
// hierarchy) and a sweep in isolation (the fastest of 15 repetitions, so other jobs on the
// machine do not count).
// Usage: bench_gather [--quick] [--runs N] [--threads N] [--micro] [--save FILE | --compare FILE]
//                     [box_room|cornell|furnace] [eps ...]
// --quick (CI smoke run, no timing judged): one run, --micro, threshold 0.2 unless given.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstdint>
#include <cstring>
#include <map>
#include <string>
#include <vector>

#include "radiosity/builtin_scenes.h"
#include "radiosity/compare.h"
#include "radiosity/gather_plan.h"
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
// The fastest of `reps` calls of f, in seconds.
template <class F>
double fastest(int reps, F&& f) {
    double best = 1e300;
    for (int r = 0; r < reps; ++r) {
        const auto t0 = std::chrono::steady_clock::now();
        f();
        best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
    return best;
}

std::string micro(const Solver& solver, int threads) {
    const Hierarchy& h = solver.hierarchy();
    const LinkStore& links = solver.links();
    const Enclosure& enclosure = solver.enclosure();
    auto direct = [](int) { return Rgb{}; };
    GatherPlan plan;
    CouplingSums fsum;
    fsum.reset(h.nodes.size());
    const int reps = 15;
    double t_build = 1e300, t_radio = 1e300;
    for (int r = 0; r < reps; ++r) {
        t_build = std::min(t_build, fastest(1, [&] { plan.build(h, links, threads); }));
        t_radio = std::min(t_radio, fastest(1, [&] { plan.prepare_radiometry(h, links, enclosure, direct, threads); }));
    }
    const double t_unit = fastest(reps, [&] { plan.sweep(true, &fsum, threads); });
    const double t_direct = fastest(reps, [&] { coupling_sums(h, links, fsum, threads); });
    plan.prepare_radiometry(h, links, enclosure, direct, threads);
    const double t_sweep = fastest(reps, [&] { plan.sweep(false, nullptr, threads); });
    const double n = double(std::max<int64_t>(1, plan.link_count()));
    char line[400];
    std::snprintf(line, sizeof line,
                  "    micro (%lld links, fastest of %d): build %.2f ms, radiometric part %.2f ms, unit sweep %.2f ms "
                  "(without a plan %.2f ms), sweep %.2f ms = %.1f ns per link; (build + radiometric part) / sweep %.2f\n",
                  (long long)plan.link_count(), reps, 1e3 * t_build, 1e3 * t_radio, 1e3 * t_unit, 1e3 * t_direct,
                  1e3 * t_sweep, 1e9 * t_sweep / n, (t_build + t_radio) / t_sweep);
    return line;
}
}  // namespace

int main(int argc, char** argv) {
    int runs = 3, threads = 0;
    bool do_micro = false;
    std::string name = "box_room", save, compare;
    std::vector<double> eps;
    bool quick = false;
    for (int i = 1; i < argc; ++i) {
        std::string a = argv[i];
        if (a == "--quick") quick = true, runs = 1, do_micro = true;
        else if (a == "--runs" && i + 1 < argc) runs = std::max(1, std::atoi(argv[++i]));
        else if (a == "--threads" && i + 1 < argc) threads = std::atoi(argv[++i]);
        else if (a == "--micro") do_micro = true;
        else if (a == "--save" && i + 1 < argc) save = argv[++i];
        else if (a == "--compare" && i + 1 < argc) compare = argv[++i];
        else if (a == "box_room" || a == "cornell" || a == "furnace") name = a;
        else eps.push_back(std::atof(a.c_str()));
    }
    if (eps.empty()) eps = quick ? std::vector<double>{0.2} : std::vector<double>{0.05, 0.02};
    SceneDesc scene = name == "cornell" ? scenes::cornell_box(8)
                      : name == "furnace" ? scenes::furnace_cube(0.5, 1.0, 4)
                                          : scenes::box_room(8);
    // Saved corners: per threshold a record (eps, count, count floats).
    std::map<double, std::vector<float>> reference;
    if (!compare.empty()) {
        FILE* f = std::fopen(compare.c_str(), "rb");
        if (!f) { std::fprintf(stderr, "cannot read %s\n", compare.c_str()); return 1; }
        double e;
        uint64_t n;
        while (std::fread(&e, sizeof e, 1, f) == 1 && std::fread(&n, sizeof n, 1, f) == 1) {
            std::vector<float>& v = reference[e];
            v.resize(size_t(n));
            if (std::fread(v.data(), sizeof(float), v.size(), f) != v.size()) break;
        }
        std::fclose(f);
    }
    FILE* out = save.empty() ? nullptr : std::fopen(save.c_str(), "wb");
    std::printf("scene: %s, %zu input polygons, %d runs (times are medians)\n\n", name.c_str(), scene.polygon_count(), runs);
    std::printf("| eps | elements | links | rays | sweeps | link-sweeps | gather s | gather ns per link-sweep | sweeps ns per "
                "link-sweep | plans | plan s | plan / sweep | closure s | total s |%s\n", compare.empty() ? "" : " NRMSE vs saved |");
    std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|%s\n", compare.empty() ? "" : "---|");
    for (double e : eps) {
        Settings st;
        st.error_threshold = e;
        st.threads = threads;
        std::vector<double> gather, per_link, sweep_per_link, plan, plan_per_sweep, closure, total;
        Stats s;
        std::vector<float> corners;
        std::string micro_line;
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
            if (do_micro && r + 1 == runs) micro_line = micro(solver, threads);
        }
        std::printf("| %g | %lld | %lld | %lld | %d | %lld | %.3f | %.1f | %.1f | %lld | %.4f | %.2f | %.3f | %.3f |", e,
                    (long long)s.elements, (long long)s.links, (long long)s.rays, s.iterations, (long long)s.link_sweeps,
                    median(gather), median(per_link), median(sweep_per_link), (long long)s.gather_plans, median(plan),
                    median(plan_per_sweep), median(closure), median(total));
        if (!compare.empty()) {
            auto it = reference.find(e);
            if (it != reference.end() && it->second.size() == corners.size()) std::printf(" %.3g |", nrmse(corners, it->second));
            else std::printf(" (not in the saved file) |");
        }
        std::printf("\n%s", micro_line.c_str());
        if (out) {
            const uint64_t n = corners.size();
            std::fwrite(&e, sizeof e, 1, out);
            std::fwrite(&n, sizeof n, 1, out);
            std::fwrite(corners.data(), sizeof(float), corners.size(), out);
        }
    }
    if (out) std::fclose(out);
    return 0;
}
