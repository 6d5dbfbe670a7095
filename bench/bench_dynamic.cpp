// Dynamic benchmark: the paper's Table 2 rows for our built-in box room (full solve with and
// without the 3.5 criterion, the paper's box move as an incremental update, and the update /
// full re-solve ratio), plus the drag of 30 small moves. Medians over --runs runs.
// Usage: bench_dynamic [--quick] [--runs N] [--preset DRAFT|MEDIUM|HIGH] [--no-drag]
//   --quick (CI smoke run, no timing judged): DRAFT, one run, a drag of 3 steps; options given
//   after it override it.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "radiosity/builtin_scenes.h"
#include "radiosity/compare.h"
#include "radiosity/solver.h"

using namespace radiosity;

namespace {
std::array<double, 16> translation(Vec3 t) { return {1, 0, 0, t.x, 0, 1, 0, t.y, 0, 0, 1, t.z, 0, 0, 0, 1}; }
double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}
// The built-in box room with Box1 shifted (its move in the paper: (114.4,129.2) -> (150,190)).
SceneDesc room(Vec3 off) {
    SceneDesc s;
    scenes::add_box(s, "room", -1, {0, 0, 0}, {300, 300, 250}, 8, Rgb::all(0.7), {}, true);
    scenes::add_grid(s, "light", -1, {Vec3{120, 120, 249}, Vec3{120, 180, 249}, Vec3{180, 180, 249}, Vec3{180, 120, 249}}, 1, 1,
                     {}, Rgb::all(12.0), false);
    int c1 = s.add_cluster("Box1");
    scenes::add_box(s, "Box1", c1, Vec3{84.4, 99.2, 0} + off, Vec3{144.4, 159.2, 100} + off, 2, Rgb{0.7, 0.3, 0.2}, {});
    int c2 = s.add_cluster("Box2");
    scenes::add_box(s, "Box2", c2, {200, 200, 0}, {260, 250, 60}, 2, Rgb{0.2, 0.4, 0.7}, {});
    return s;
}
}  // namespace

int main(int argc, char** argv) {
    int runs = 3;
    int drag_steps = 30;
    std::string preset = "MEDIUM";
    for (int i = 1; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--quick")) runs = 1, drag_steps = 3, preset = "DRAFT";
        else if (!std::strcmp(argv[i], "--runs") && i + 1 < argc) runs = std::max(1, std::atoi(argv[++i]));
        else if (!std::strcmp(argv[i], "--preset") && i + 1 < argc) preset = argv[++i];
        else if (!std::strcmp(argv[i], "--no-drag")) drag_steps = 0;
        else {
            std::fprintf(stderr, "bench_dynamic: unknown argument %s\n", argv[i]);
            return 2;
        }
    }
    const Vec3 move{35.6, 60.8, 0};
    Settings st = Settings::preset(preset);
    std::vector<double> t_full, t_full_no35, t_update, t_adjust, t_full_after;
    Stats s_full, s_no35, s_upd;
    double err = 0, noise = 0;
    for (int r = 0; r < runs; ++r) {
        Solver a(room({}), st);
        a.solve();
        s_full = a.stats();
        t_full.push_back(s_full.seconds_total);
        Settings st2 = st;
        st2.progressive_refinement = false;
        Solver b(room({}), st2);
        b.solve();
        s_no35 = b.stats();
        t_full_no35.push_back(s_no35.seconds_total);
        a.move_object(2, translation(move));
        a.update();
        s_upd = a.stats();
        t_update.push_back(s_upd.seconds_total);
        t_adjust.push_back(s_upd.seconds_adjust);
        Solver c(room(move), st);
        c.solve();
        t_full_after.push_back(c.stats().seconds_total);
        err = nrmse(a.all_corner_radiance(), c.all_corner_radiance());
        // The method's own noise floor: two full solves of the moved scene that differ only
        // in the seed of their rays. An update reuses links (and their rays) a full solve
        // would make otherwise, so it cannot match one more closely than this, bar luck.
        Settings st3 = st;
        st3.seed = st.seed + 1;
        Solver e(room(move), st3);
        e.solve();
        noise = nrmse(e.all_corner_radiance(), c.all_corner_radiance());
    }
    std::printf("box room (built-in, %s, %d runs, medians)\n\n", preset.c_str(), runs);
    std::printf("| | ours | paper (SGI O2) |\n|---|---|---|\n");
    std::printf("| input surfaces | %lld | 19 |\n| objects | 2 | 2 |\n", (long long)s_full.input_surfaces);
    std::printf("| elements | %lld | 5,723 |\n| links | %lld | 4,785 |\n", (long long)s_full.elements, (long long)s_full.links);
    std::printf("| cluster links | %lld | |\n| obj-env links | %lld | |\n| env-env links | %lld | |\n",
                (long long)s_full.cluster_links, (long long)s_full.obj_env_links, (long long)s_full.env_env_links);
    std::printf("| full solve, s (with 3.5) | %.3f | 32.6 |\n| full solve, s (without 3.5) | %.3f | 35.1 |\n",
                median(t_full), median(t_full_no35));
    std::printf("| links without 3.5 | %lld | |\n", (long long)s_no35.links);
    std::printf("| env-env links tested / rejected by outcodes / rays clear of the moved boxes / recomputed | %lld / %lld / %lld / %lld (%.1f %% recomputed) | 22 %% recomputed |\n",
                (long long)s_upd.env_env_links_tested, (long long)s_upd.env_env_links_rejected,
                (long long)s_upd.env_env_links_rays_clear, (long long)s_upd.env_env_links_recomputed,
                100.0 * s_upd.env_env_links_recomputed / std::max<int64_t>(1, s_upd.env_env_links_tested));
    std::printf("| link update (AdjustSystem), s | %.3f | 2.64 |\n| whole incremental update, s | %.3f | |\n",
                median(t_adjust), median(t_update));
    std::printf("| full re-solve of the moved scene, s | %.3f | |\n| update / full re-solve | %.1f %% | 8 %% |\n",
                median(t_full_after), 100.0 * median(t_update) / median(t_full_after));
    std::printf("| NRMSE incremental vs full re-solve | %.4f | |\n", err);
    std::printf("| NRMSE full re-solve vs full re-solve with another seed (noise floor) | %.4f | |\n", noise);
    auto phases = [](const char* what, const Stats& st) {
        std::printf("\n%s (last run): %d iterations, %d refine rounds;", what, st.iterations, st.refine_rounds);
        double gather = 0;
        for (const auto& p : st.phases) {
            std::printf(" %s %.3f", p.first.c_str(), p.second);
            if (p.first == "gather") gather = p.second;
        }
        const double ls = double(std::max<int64_t>(1, st.link_sweeps));
        std::printf(" s\n  rays:");
        int64_t rays = 0;
        for (const auto& p : st.phase_rays)
            if (p.second) std::printf(" %s %lld", p.first.c_str(), (long long)p.second), rays += p.second;
        std::printf(" (%lld in all)\n  gathering: %lld link-sweeps; gather phase %.1f ns, sweeps alone %.1f ns per link-sweep; "
                    "%lld gather plans built in %.4f s\n",
                    (long long)rays, (long long)st.link_sweeps, 1e9 * gather / ls, 1e9 * st.seconds_sweeps / ls,
                    (long long)st.gather_plans, st.seconds_gather_plan);
    };
    phases("full solve phases", s_full);
    phases("update phases", s_upd);

    if (drag_steps == 0) return 0;
    // Drag: the same total move in drag_steps equal steps.
    Solver d(room({}), st);
    d.solve();
    std::vector<double> steps;
    for (int k = 1; k <= drag_steps; ++k) {
        d.move_object(2, translation(move * (double(k) / drag_steps)));
        d.update();
        steps.push_back(d.stats().seconds_total);
    }
    Solver f(room(move), st);
    f.solve();
    std::printf("\ndrag of %d steps: median step %.3f s (full solve %.3f s, ratio %.1f %%), NRMSE after the last step vs full %.4f\n",
                drag_steps, median(steps), f.stats().seconds_total, 100.0 * median(steps) / f.stats().seconds_total,
                nrmse(d.all_corner_radiance(), f.all_corner_radiance()));
    return 0;
}
