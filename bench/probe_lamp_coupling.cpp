// Probe for bench/results/closure_bias.md: does a wall leaf get the right direct coupling to a
// ceiling lamp? An empty closed room (3 x 3 x 2.5, 8 x 8 per face, rho 0.7) with a two-sided
// 0.6 m lamp 1 cm under its ceiling, solved at a preset; for every wall leaf, the lamp's share
// of its couplings as the sweep adds it (K of the links from the lamp at the leaf and its element
// ancestors, K x cosine for the cluster links above) against an 8 x 8-point average of Lambert's
// point-to-polygon form factor over the leaf. Area-weighted ratios by the leaf's height.
//
//     build/bench/probe_lamp_coupling MEDIUM
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "radiosity/builtin_scenes.h"
#include "radiosity/geometry.h"
#include "radiosity/solver.h"

using namespace radiosity;

int main(int argc, char** argv) {
    const std::string preset = argc > 1 ? argv[1] : "MEDIUM";
    SceneDesc sc;
    scenes::add_box(sc, "room", -1, {0, 0, 0}, {3, 3, 2.5}, 8, Rgb::all(0.7), Rgb{}, true, false);
    const Vec3 c0{1.2, 1.2, 2.49}, c1{1.2, 1.8, 2.49}, c2{1.8, 1.8, 2.49}, c3{1.8, 1.2, 2.49};
    scenes::add_grid(sc, "lamp", -1, {c0, c1, c2, c3}, 1, 1, Rgb{}, Rgb::all(10), true);
    Solver s(sc, Settings::preset(preset));
    s.solve();
    const Hierarchy& h = s.hierarchy();
    const LinkStore& links = s.links();
    Poly lamp;
    lamp.n = 4;
    lamp.v = {h.to_internal(c0), h.to_internal(c1), h.to_internal(c2), h.to_internal(c3)};
    const Vec3 down = lamp.normal();
    const double edges[] = {0, 1.0, 2.0, 2.3, 2.45, 2.5};
    constexpr int kBands = 5;
    double sum_k[kBands] = {0}, sum_ref[kBands] = {0}, sum_cluster[kBands] = {0};
    int leaves[kBands] = {0};
    for (size_t id = 0; id < h.nodes.size(); ++id) {
        const Node& L = h.nodes[id];
        if (L.dead || L.is_cluster() || !L.children.empty() || L.surface < 0) continue;
        if (L.object != 0 || std::fabs(L.normal.z) > 0.1) continue;  // the room's walls
        double k_cluster = 0, k_element = 0;
        for (int a = int(id); a >= 0; a = h.nodes[size_t(a)].parent) {
            const Node& N = h.nodes[size_t(a)];
            for (int li : N.in_links) {
                const Link& l = links[size_t(li)];
                if (l.dead || !l.active || h.nodes[size_t(l.src)].object != 1) continue;
                if (N.is_cluster()) k_cluster += l.K * std::max(0.0, -dot(L.normal, l.dir));
                else k_element += l.K;
            }
        }
        constexpr int G = 8;
        double ref = 0;
        for (int i = 0; i < G; ++i)
            for (int j = 0; j < G; ++j) {
                const Vec3 p = L.poly.sample((i + 0.5) / G, (j + 0.5) / G);
                // Two-sided: a point above the lamp's plane sees its top.
                const Vec3 side = dot(p - lamp.v[0], down) >= 0 ? down : down * -1.0;
                ref += point_polygon_form_factor(p, L.normal, lamp, side);
            }
        ref /= G * G;
        const double z = (h.origin + L.center * h.unit).z;
        int b = 0;
        while (b < kBands - 1 && z >= edges[b + 1]) ++b;
        sum_k[b] += L.area * (k_cluster + k_element);
        sum_cluster[b] += L.area * k_cluster;
        sum_ref[b] += L.area * ref;
        ++leaves[b];
    }
    for (int b = 0; b < kBands; ++b)
        if (leaves[b] > 0)
            std::printf("%s: walls z in [%.2f, %.2f) m: %d leaves, lamp coupling / dense reference %.4f (%.0f %% through cluster links)\n",
                        preset.c_str(), edges[b], edges[b + 1], leaves[b], sum_k[b] / sum_ref[b],
                        100 * sum_cluster[b] / std::max(1e-300, sum_k[b]));
}
