// Static-solve benchmark and native demo: solves a built-in scene at several error
// thresholds and prints elements, links, rays and seconds per phase (a markdown table).
// Usage: bench_static [--quick] [box_room|cornell|furnace] [eps ...]
//   --quick (CI smoke run, no timing judged): threshold 0.2 only unless given.
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "radiosity/builtin_scenes.h"
#include "radiosity/solver.h"

using namespace radiosity;

int main(int argc, char** argv) {
    std::string name = "box_room";
    std::vector<double> eps;
    bool quick = false;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--quick") quick = true;
        else if (a == "box_room" || a == "cornell" || a == "furnace") name = a;
        else {
            char* end = nullptr;
            const double e = std::strtod(a.c_str(), &end);
            if (end == a.c_str() || *end != '\0' || !(e > 0)) {
                std::fprintf(stderr, "bench_static: not a scene or a positive threshold: %s\n", a.c_str());
                return 2;
            }
            eps.push_back(e);
        }
    }
    if (eps.empty()) eps = quick ? std::vector<double>{0.2} : std::vector<double>{0.2, 0.1, 0.05, 0.02, 0.01};
    SceneDesc scene = name == "cornell" ? scenes::cornell_box(8)
                      : name == "furnace" ? scenes::furnace_cube(0.5, 1.0, 4)
                                          : scenes::box_room(8);
    std::printf("scene: %s, %zu input polygons, %zu objects\n\n", name.c_str(), scene.polygon_count(),
                scene.objects().size());
    std::printf("| eps | elements | links | cluster links | rays | iterations | build s | link s | solve s | total s |\n");
    std::printf("|---|---|---|---|---|---|---|---|---|---|\n");
    for (double e : eps) {
        Settings st;
        st.error_threshold = e;
        Solver solver(scene, st);
        solver.solve();
        const Stats& s = solver.stats();
        std::printf("| %g | %lld | %lld | %lld | %lld | %d | %.3f | %.3f | %.3f | %.3f |\n", e, (long long)s.elements,
                    (long long)s.links, (long long)s.cluster_links, (long long)s.rays, s.iterations, s.seconds_build,
                    s.seconds_link, s.seconds_solve, s.seconds_total);
    }
    return 0;
}
