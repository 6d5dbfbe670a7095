// The resolution limit holds for clusters as for elements: a cluster smaller than four of the
// smallest elements a preset resolves (in area and in extent) is not split, so a finely
// tessellated object (Bevel and Subdivision Surface make thousands of polygons below the
// minimum element size) keeps cluster links where its pieces meet, instead of one link per
// pair of nearby polygons. Its light must not depend on how finely it is tessellated.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "test_util.h"

using namespace radiosity;
using namespace radiosity::testing;

namespace {

// A room lit by a ceiling lamp with a small trough on its floor: a half cylinder (radius
// 0.15 m, 0.4 m long, Suzanne's size) open upward, of `around` x `along` quads, each seeing
// most of the others across the hollow (an ear of a subdivided Suzanne).
SceneDesc trough_room(int around, int along) {
    SceneDesc s = lamp_room(4);
    ObjectDesc o;
    o.name = "trough";
    o.cluster = s.add_cluster("trough");
    for (int j = 0; j <= along; ++j)
        for (int i = 0; i <= around; ++i) {
            const double a = kPi * i / around;  // from one rim (a = 0) under the axis to the other
            o.vertices.push_back({1.8 + 0.4 * j / along, 2.0 + 0.15 * std::cos(a), 0.15 - 0.15 * std::sin(a)});
        }
    auto at = [&](int i, int j) { return int32_t(j * (around + 1) + i); };
    for (int j = 0; j < along; ++j)
        for (int i = 0; i < around; ++i) {
            o.loop_starts.push_back(int32_t(o.corner_verts.size()));
            o.loop_totals.push_back(4);
            // Front faces toward the axis (the hollow).
            for (int v : {at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)}) o.corner_verts.push_back(v);
            o.reflectance.push_back(Rgb{0.7, 0.5, 0.4});
            o.emission.push_back({});
            o.two_sided.push_back(true);
        }
    s.add_object(std::move(o));
    return s;
}

struct Baked {
    Rgb trough, room;
    double trough_corners = 0;  // mean corner output (green) of the trough
    int64_t links = 0, surfaces = 0;
};

Baked bake(int around, int along) {
    Solver s(trough_room(around, along), Settings::preset("DRAFT"));
    s.solve();
    Baked b;
    b.trough = object_front_radiance(s, 2);
    b.room = object_front_radiance(s, 0);
    const std::vector<float> c = s.corner_radiance(2);
    for (size_t k = 1; k < c.size(); k += 3) b.trough_corners += c[k];
    b.trough_corners /= double(c.size() / 3);
    b.links = s.stats().links;
    b.surfaces = s.stats().input_surfaces;
    std::printf("[ figure ] trough of %d x %d quads: %lld links for %lld surfaces; trough %.4f (corners %.4f) room %.4f\n",
                around, along, (long long)b.links, (long long)b.surfaces, b.trough.g, b.trough_corners, b.room.g);
    return b;
}

}  // namespace

TEST(ResolutionLimit, FinelyTessellatedFurnitureKeepsItsLightWithLinksInProportion) {
    const Baked coarse = bake(4, 4);   // pieces above the minimum element size
    const Baked fine = bake(16, 32);   // 512 pieces, each below it
    const Baked finer = bake(32, 64);  // 4x the pieces again
    // The same shape, the same light, whatever the tessellation: the output (the final gather
    // reads each corner's light from the corner) and the room around.
    for (const Baked* b : {&fine, &finer}) {
        EXPECT_NEAR(b->trough_corners, coarse.trough_corners, 0.02 * coarse.trough_corners);
        EXPECT_NEAR(b->room.g, coarse.room.g, 0.02 * coarse.room.g);
    }
    // 128 times the pieces of the coarse trough for under 10 times its links (a link per pair
    // of small pieces that see each other across the hollow took 15 times).
    std::printf("[ figure ] links x%.2f for x%.2f surfaces\n", double(finer.links) / double(coarse.links),
                double(finer.surfaces) / double(coarse.surfaces));
    EXPECT_LT(finer.links, 10 * coarse.links);
}

namespace {

// A corrugated sheet of one object over the floor of a lit room: three waves across, finely
// tessellated (a subdivided Suzanne's folds). A face on one flank sees the next flank across
// the trough, while the sub-cluster holding that flank straddles the face's plane or overlaps
// it: the point model fails, and both ends are below the smallest element.
SceneDesc corrugated_room(int n) {
    SceneDesc s = lamp_room(4);
    ObjectDesc o;
    o.name = "sheet";
    o.cluster = s.add_cluster("sheet");
    const int m = n / 4;
    for (int j = 0; j <= m; ++j)
        for (int i = 0; i <= n; ++i)
            o.vertices.push_back({1.8 + 0.4 * i / n, 1.8 + 0.4 * j / m, 0.5 + 0.05 * std::sin(2 * kPi * 3 * i / n)});
    for (int j = 0; j < m; ++j)
        for (int i = 0; i < n; ++i) {
            o.loop_starts.push_back(int32_t(o.corner_verts.size()));
            o.loop_totals.push_back(4);
            for (int32_t k : {j * (n + 1) + i, j * (n + 1) + i + 1, (j + 1) * (n + 1) + i + 1, (j + 1) * (n + 1) + i})
                o.corner_verts.push_back(k);
            o.reflectance.push_back(Rgb::all(0.7));
            o.emission.push_back({});
            o.two_sided.push_back(true);
        }
    s.add_object(std::move(o));
    return s;
}

}  // namespace

// A link whose point model fails (its ends overlap) where neither end may split any further
// carries the coupling the exact kernel gives, not none: the light between the two sides of
// a fold (a subdivided Suzanne's ear and cheek) stays in the solution.
TEST(ResolutionLimit, LinksAtTheLimitCarryTheirCoupling) {
    Solver s(corrugated_room(48), Settings::preset("DRAFT"));
    s.solve();
    const Hierarchy& h = s.hierarchy();
    double K = 0, K_unoccluded = 0, exact = 0;
    int count = 0;
    for (const Link& l : s.links()) {
        if (l.dead || !l.active || !l.must_refine || h.nodes[size_t(l.rcv)].is_cluster()) continue;
        const Node& Q = h.nodes[size_t(l.rcv)];
        const Node& P = h.nodes[size_t(l.src)];
        if (Q.object != 2 || P.object != 2) continue;
        ++count;
        K += l.K;
        K_unoccluded += l.K_unoccluded;
        // Nothing stands between the fold's two sides: the unoccluded polygon-to-polygon form
        // factor to every surface of the sender is the reference.
        auto add = [&](const Poly& p) { exact += form_factor(Q.poly, p, 3); };
        if (!P.is_cluster()) add(P.poly);
        else
            for (int i = P.surf_begin; i < P.surf_end; ++i) add(h.surface_geom[size_t(i)].poly);
    }
    std::printf("[ figure ] %d links at the limit: K %.4f unoccluded %.4f exact %.4f\n", count, K, K_unoccluded, exact);
    ASSERT_GT(count, 10);
    EXPECT_NEAR(K_unoccluded, exact, 0.1 * exact);
    EXPECT_NEAR(K, exact, 0.1 * exact);
}
