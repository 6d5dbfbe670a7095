// Probe for the light a coarse solution adds (bench/results/interior_native.md, "Where MEDIUM's
// time goes"): the built-in box room solved at MEDIUM without the final gather, at a given
// element floor, closure rays and reflectance, and what its leaves absorb against what its
// emitters emit. Between two floors the ratio says how much light per bounce one solution's
// links carry more than the other's (with reflectance 0.01, the first bounce alone).
//
//   probe_coarse_bias MIN_AREA_FRACTION CLOSURE_RAYS [REFLECTANCE]
//   e.g. build/bench/probe_coarse_bias 1e-5 0 0.01; build/bench/probe_coarse_bias 1e-4 0 0.01
#include <cstdio>
#include <cstdlib>

#include "radiosity/builtin_scenes.h"
#include "radiosity/solver.h"

using namespace radiosity;

int main(int argc, char** argv) {
    if (argc < 3) {
        std::fprintf(stderr, "usage: %s MIN_AREA_FRACTION CLOSURE_RAYS [REFLECTANCE]\n", argv[0]);
        return 2;
    }
    Settings st = Settings::preset("MEDIUM");
    st.gather_rays = 0;
    st.min_area_fraction = std::atof(argv[1]);
    st.closure_rays = std::atoi(argv[2]);
    SceneDesc scene = scenes::box_room(8);
    if (argc > 3) {
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
