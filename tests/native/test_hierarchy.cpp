// The hierarchy on its own: what a build, a material edit and a removal leave in it, apart
// from any update of a solution.
#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <utility>
#include <vector>

#include "test_util.h"

using namespace radiosity;
using namespace radiosity::testing;

namespace {

// The shape of an object's cluster tree: per node in depth-first order, its surface count
// and its centre relative to the object's.
std::vector<std::pair<int, Vec3>> tree_shape(const Solver& s, int object) {
    const Hierarchy& h = s.hierarchy();
    const int top = h.object_node[size_t(object)];
    std::vector<std::pair<int, Vec3>> out;
    std::function<void(int)> walk = [&](int id) {
        const Node& n = h.nodes[size_t(id)];
        if (!n.is_cluster()) return;
        out.push_back({n.surf_end - n.surf_begin, n.center - h.nodes[size_t(top)].center});
        for (int c : n.children) walk(c);
    };
    walk(top);
    return out;
}

}  // namespace

TEST(Hierarchy, AppliedMaterialsAreThoseAFreshBuildGives) {
    // Hierarchy::apply_materials after an edit of the scene: every element (split ones too)
    // and every cluster as a build of the edited scene makes them; radiance left alone.
    SceneDesc s = two_box_room();
    Hierarchy h;
    h.build(s, true);
    int split = -1;  // a face of the room the edit makes white, split twice
    for (const Surface& f : h.surfaces)
        if (split < 0 && h.prims[size_t(f.prim)].object == 0 && h.prims[size_t(f.prim)].face % 2 == 0) split = f.root;
    ASSERT_GE(split, 0);
    h.subdivide(split);
    h.subdivide(h.nodes[split].children[0]);
    for (size_t i = 0; i < h.nodes.size(); ++i) h.nodes[i].L = Rgb::all(0.25);
    ObjectDesc& walls = s.objects_mut()[0];
    for (size_t f = 0; f < walls.reflectance.size(); ++f) walls.reflectance[f] = f % 2 ? Rgb{0.1, 0.2, 0.3} : Rgb::all(0.9);
    s.objects_mut()[1].emission.assign(1, Rgb::all(3.0));
    h.apply_materials(s);
    Hierarchy fresh;
    fresh.build(s, true);
    ASSERT_LE(fresh.nodes.size(), h.nodes.size());  // the same tree, with the splits after it
    for (size_t i = 0; i < fresh.nodes.size(); ++i) {
        const Node &a = h.nodes[i], &b = fresh.nodes[i];
        ASSERT_EQ(a.is_cluster(), b.is_cluster()) << i;
        if (a.is_cluster()) {
            EXPECT_EQ(a.rho_max, b.rho_max) << i;
        } else {
            EXPECT_EQ(a.rho.max(), b.rho.max()) << i;
            EXPECT_EQ(a.rho.mean(), b.rho.mean()) << i;
            EXPECT_EQ(a.emission.max(), b.emission.max()) << i;
        }
    }
    for (size_t i = fresh.nodes.size(); i < h.nodes.size(); ++i) {  // the split elements
        const Node& e = h.nodes[i];
        EXPECT_EQ(e.rho.mean(), h.nodes[split].rho.mean()) << i;
        EXPECT_EQ(e.emission.max(), 0.0) << i;
    }
    EXPECT_EQ(h.nodes[split].rho.max(), 0.9);
    for (size_t i = 0; i < h.nodes.size(); ++i) EXPECT_EQ(h.nodes[i].L.max(), 0.25) << i;
}

TEST(Hierarchy, RetiringCountsTheElementsAndFreesTheirLinks) {
    // retire_below: every node below a twice-split element dies with empty link lists and the
    // element becomes a leaf; remove_object counts the element nodes it retired.
    SceneDesc s = two_box_room();
    Hierarchy h;
    h.build(s, true);
    const int split = h.surfaces[0].root;
    h.subdivide(split);
    h.subdivide(h.nodes[split].children[1]);
    const std::vector<int> below = {h.nodes[split].children[0], h.nodes[h.nodes[split].children[1]].children[2]};
    for (int id : below) h.nodes[id].in_links = h.nodes[id].out_links = {0, 1};
    EXPECT_EQ(h.retire_below(split), 8);
    EXPECT_TRUE(h.nodes[split].is_leaf());
    EXPECT_FALSE(h.nodes[split].dead);
    for (int id : below) {
        EXPECT_TRUE(h.nodes[id].dead) << id;
        EXPECT_TRUE(h.nodes[id].in_links.empty() && h.nodes[id].out_links.empty()) << id;
    }
    int elements = 0;
    for (int id : h.object_nodes(1)) elements += h.nodes[id].is_cluster() ? 0 : 1;
    ASSERT_GT(elements, 0);
    EXPECT_EQ(h.remove_object(1).elements, elements);
}

TEST(Hierarchy, SurfaceTotalsCountLiveSurfacesOnly) {
    // Hierarchy::surface_totals: area, and area x largest emission and reflectance channel,
    // over every oriented surface (a two-sided floor twice, a one-sided lamp once), in the
    // internal frame; a removed object's surfaces drop out.
    SceneDesc s;
    scenes::add_grid(s, "floor", -1, {Vec3{0, 0, 0}, Vec3{2, 0, 0}, Vec3{2, 1, 0}, Vec3{0, 1, 0}}, 2, 1,
                     Rgb{0.2, 0.5, 0.3}, {}, true);
    scenes::add_grid(s, "lamp", -1, {Vec3{0, 0, 1}, Vec3{0, 1, 1}, Vec3{1, 1, 1}, Vec3{1, 0, 1}}, 1, 1,
                     Rgb::all(0.1), Rgb{1, 4, 2}, false);
    Hierarchy h;
    h.build(s, true);
    const double u2 = h.unit * h.unit;  // world area / internal area
    auto expect_near = [](double got, double want) { EXPECT_NEAR(got, want, 1e-9 * want) << want; };
    const Hierarchy::SurfaceTotals all = h.surface_totals();
    expect_near(all.area, 5.0 / u2);
    expect_near(all.emission, 4.0 / u2);
    expect_near(all.reflectance, (2 * 0.5 + 2 * 0.5 + 0.1) / u2);
    h.subdivide(h.surfaces[0].root);  // the roots' own area and material: splits change nothing
    EXPECT_EQ(h.surface_totals().area, all.area);
    h.remove_object(1);
    const Hierarchy::SurfaceTotals without_lamp = h.surface_totals();
    expect_near(without_lamp.area, 4.0 / u2);
    EXPECT_EQ(without_lamp.emission, 0.0);
    expect_near(without_lamp.reflectance, 2.0 / u2);
}

// An update keeps a moved object's cluster tree; a full solve builds it where the object now
// stands. Built along rounding-sensitive comparisons (a square box's equal extents, a grid's
// equal rows), the two trees differed, and with them the cluster links: the box top came out
// refined elsewhere (3 % NRMSE on the box, 0.67 % overall).
TEST(Hierarchy, ObjectTreeDoesNotDependOnWhereTheObjectStands) {
    Settings st = Settings::preset("MEDIUM");
    st.rays_per_link = 32;  // as the move tests solve this scene (test_dynamic.cpp)
    Solver a(panel_over_box({0.6, 0.3, 0.4}), st);
    Solver b(panel_over_box({-0.1, 0.7, 0.4}), st);
    a.solve();
    b.solve();
    const auto ta = tree_shape(a, 2), tb = tree_shape(b, 2);
    ASSERT_EQ(ta.size(), tb.size());
    ASSERT_GT(ta.size(), 3u);
    for (size_t i = 0; i < ta.size(); ++i) {
        EXPECT_EQ(ta[i].first, tb[i].first) << "node " << i;
        EXPECT_LT(length(ta[i].second - tb[i].second), 1e-9) << "node " << i;
    }
}

TEST(Hierarchy, SamplerTreeHoldsEachClusterSurfacesOnceWithinTheFanOut) {
    // A draw from a large cluster descends the samplers' tree (TreeSampler): per cluster, the
    // nodes it picks among must hold each of its surfaces exactly once (a surface missing is
    // never drawn, one held twice drawn twice as often), no more of them than the fan-out
    // allows unless the cluster has more children, and each cluster record's own range must
    // be the one sampler_first gives.
    SceneDesc s = lamp_room(24);  // a room of 3,456 quads: a deep binary object tree
    const int c = s.add_cluster("Box");
    scenes::add_box(s, "Box", c, {1, 1, 0}, {2, 2, 1}, 6, Rgb::all(0.5), {});
    Hierarchy h;
    h.build(s, true);
    int clusters = 0, deep = 0;
    for (size_t id = 0; id < h.nodes.size(); ++id) {
        const Node& n = h.nodes[id];
        if (!n.is_cluster() || n.dead) continue;
        ++clusters;
        const int first = h.sampler_first[id], m = h.sampler_first[id + 1] - first;
        EXPECT_LE(size_t(m), std::max(Hierarchy::kSamplerFanOut, n.children.size())) << "cluster " << id;
        std::vector<int> held;  // surface_order positions the records hold
        double area = 0;
        for (int k = first; k < first + m; ++k) {
            const Hierarchy::SamplerRecord& sc = h.sampler_records[size_t(k)];
            const Node& e = h.nodes[size_t(sc.id)];
            area += sc.area;
            if (sc.cluster) {
                EXPECT_EQ(sc.first, h.sampler_first[size_t(sc.id)]);
                EXPECT_EQ(sc.count, h.sampler_first[size_t(sc.id) + 1] - h.sampler_first[size_t(sc.id)]);
                for (int i = e.surf_begin; i < e.surf_end; ++i) held.push_back(i);
                if (e.parent != int(id)) ++deep;
            } else {
                ASSERT_GE(sc.geom, 0);
                held.push_back(sc.geom);
            }
        }
        std::sort(held.begin(), held.end());
        std::vector<int> want(size_t(n.surf_end - n.surf_begin));
        for (size_t i = 0; i < want.size(); ++i) want[i] = n.surf_begin + int(i);
        EXPECT_EQ(held, want) << "cluster " << id;
        EXPECT_NEAR(area, n.area, 1e-9 * n.area) << "cluster " << id;
    }
    EXPECT_GT(clusters, 100);
    EXPECT_GT(deep, 0);  // records below the children: the fan-out is in use
}
