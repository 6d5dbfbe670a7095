// Probe for the light a coarse solution adds (bench/results/interior_native.md, "Where MEDIUM's
// time goes"; bench/results/coarse_outline.md): a built-in scene solved at MEDIUM without the
// final gather, at a given element floor, closure rays and reflectance, and what its
// non-emitting leaves absorb against what its emitters emit. Between two floors the ratio says
// how much light per bounce one solution's links carry more than the other's (with reflectance
// 0.01, the first bounce alone). Scenes: the paper's box room (`box`, the default) or
// `lamp_gap`, an empty closed room (3 x 3 x 2.5, reflectance 0.7) with a two-sided 0.6 m lamp
// 1 cm under its ceiling.
//
//   probe_coarse_bias MIN_AREA_FRACTION CLOSURE_RAYS [REFLECTANCE|-] [box|lamp_gap]
//   e.g. build/bench/probe_coarse_bias 1e-5 0 0.01; build/bench/probe_coarse_bias 1e-4 64 - lamp_gap
#include <cstdio>
#include <cstdlib>
#include <string>

#include "radiosity/builtin_scenes.h"
#include "radiosity/solver.h"

using namespace radiosity;

int main(int argc, char** argv) {
    if (argc < 3) {
        std::fprintf(stderr, "usage: %s MIN_AREA_FRACTION CLOSURE_RAYS [REFLECTANCE|-] [box|lamp_gap]\n", argv[0]);
        return 2;
    }
    Settings st = Settings::preset("MEDIUM");
    st.gather_rays = 0;
    st.min_area_fraction = std::atof(argv[1]);
    st.closure_rays = std::atoi(argv[2]);
    const std::string which = argc > 4 ? argv[4] : "box";
    SceneDesc scene;
    if (which == "lamp_gap") {
        scene = scenes::lamp_under_ceiling(0.01);
    } else if (which == "box") {
        scene = scenes::box_room(8);
    } else {
        std::fprintf(stderr, "unknown scene '%s' (box or lamp_gap)\n", which.c_str());
        return 2;
    }
    if (argc > 3 && std::string(argv[3]) != "-") {
        const double rho = std::atof(argv[3]);
        for (ObjectDesc& o : scene.objects_mut())
            for (Rgb& r : o.reflectance)
                if (r.max() > 0) r = Rgb::all(rho);
    }
    Solver s(scene, st);
    s.solve();
    // Per leaf: emitted E A, absorbed (1 - rho) G A with G = (L - E) / rho its irradiance / pi.
    double emitted = 0, absorbed = 0;
    for (const Node& n : s.hierarchy().nodes) {
        if (n.is_cluster() || !n.children.empty() || n.dead) continue;
        emitted += n.emission.g * n.area;
        if (n.rho.g > 0) absorbed += (1 - n.rho.g) * (n.L.g - n.emission.g) / n.rho.g * n.area;
    }
    std::printf("min_area_fraction %g, closure_rays %d: elements %lld, links %lld, absorbed / emitted %.4f\n",
                st.min_area_fraction, st.closure_rays, (long long)s.stats().elements, (long long)s.stats().links,
                absorbed / emitted);
    return 0;
}
