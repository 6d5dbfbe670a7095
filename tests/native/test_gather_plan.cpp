// The gather plan (gather_plan.h) against a Jacobi sweep over the hierarchy itself, written
// here as plainly as paper 2 states it (gather through every receiver's links, push irradiance
// down each quadtree, reflect at the leaves, pull radiance up area-weighted; then clusters, by
// Gathering::pull_up_clusters, the pass over the nodes that code outside the sweeps uses).
// The plan sums the same terms in the same order, so the two must agree bit for bit.
#include <gtest/gtest.h>

#include <cstring>
#include <functional>
#include <ostream>

#include "radiosity/enclosure.h"
#include "radiosity/gather_plan.h"
#include "radiosity/gathering.h"
#include "radiosity/transfer.h"
#include "test_util.h"

using namespace radiosity;

namespace {

using Direct = std::function<Rgb(int)>;

// The reference sweep: reads and writes the nodes and links directly.
struct ReferenceSweep {
    Hierarchy& h;
    LinkStore& links;
    const Enclosure& enclosure;
    Direct direct;

    void push_down(int id, Rgb acc, bool unit, CouplingSums* sums, double& delta) {
        Node& n = h.nodes[size_t(id)];
        const Rgb own = n.in_links.empty() ? Rgb{} : n.G;
        acc += own;
        if (n.children.empty()) {
            if (unit) {
                sums->total[size_t(id)] = acc.mean();
                sums->own[size_t(id)] = own.mean();
                return;
            }
            const ClosureFactors& k = enclosure.factors(id);
            Rgb Lnew = n.emission + n.rho * (own * k.c_own + (acc - own) * k.c_inherited + n.L * k.fill + direct(id));
            delta = std::max(delta, std::fabs((Lnew - n.L).max()));
            delta = std::max(delta, std::fabs((n.L - Lnew).max()));
            n.L = Lnew;
            n.Lmin = n.Lmax = Lnew;
            return;
        }
        Rgb sum, lo = Rgb::all(1e300), hi = Rgb::all(-1e300);
        double area = 0;
        for (int c : n.children) {
            push_down(c, acc, unit, sums, delta);
            if (unit) continue;
            const Node& k = h.nodes[size_t(c)];
            sum += k.L * k.area;
            area += k.area;
            lo = cmin(lo, k.Lmin);
            hi = cmax(hi, k.Lmax);
        }
        if (unit) return;
        n.L = area > 0 ? sum / area : n.emission;
        n.Lmin = lo;
        n.Lmax = hi;
    }

    double sweep(bool unit, CouplingSums* sums) {
        for (Node& q : h.nodes) {
            if (q.dead || q.in_links.empty()) continue;
            Rgb g;
            for (int li : q.in_links) {
                Link& l = links[size_t(li)];
                Rgb v = (unit ? Rgb::all(1.0) : sender_radiance(h, l)) * l.K;
                if (q.is_cluster()) l.value = v;
                else g += v;
            }
            q.G = g;
        }
        double delta = 0;
        for (size_t s = 0; s < h.surfaces.size(); ++s) {
            const int root = h.surfaces[s].root;
            const Vec3 n = h.nodes[size_t(root)].normal;
            Rgb acc;
            for (int a : h.ancestors_of_surface(int(s)))
                for (int li : h.nodes[size_t(a)].in_links) {
                    // Only to surfaces in a pocket the sender has surfaces in (closed pockets).
                    double c = -dot(n, links[size_t(li)].dir);
                    if (c > 0 && h.holds_pocket(links[size_t(li)].src, h.nodes[size_t(root)].pocket))
                        acc += links[size_t(li)].value * c;
                }
            push_down(root, acc, unit, sums, delta);
        }
        if (unit) return 0.0;
        // Clusters from their children, over the nodes: the hierarchy's own pass, which the
        // plan's pass over its arrays must match.
        Gathering::pull_up_clusters(h);
        return delta;
    }
};

bool same(const Rgb& a, const Rgb& b) { return std::memcmp(&a, &b, sizeof(Rgb)) == 0; }

// A solved scene whose radiances are then scrambled (deterministically), so the sweeps below
// start far from the fixed point and every term matters.
struct Solved {
    Hierarchy h;
    LinkStore links;
    Enclosure enclosure;
};

Solved solved(const SceneDesc& scene, double eps, bool clustering) {
    Settings st;
    st.error_threshold = eps;
    st.use_clustering = clustering;
    Solver solver(scene, st);
    solver.solve();
    Solved s{solver.hierarchy(), solver.links(), solver.enclosure()};
    s.enclosure.fit(s.h);
    for (size_t i = 0; i < s.h.nodes.size(); ++i) {
        Node& n = s.h.nodes[i];
        n.L = n.emission + Rgb{0.1 * double(i % 7), 0.05 * double(i % 5), 0.02 * double(i % 11)};
        ClosureFactors k;
        k.c_inherited = 0.9 + 0.01 * double(i % 13);
        k.c_own = 0.95 + 0.01 * double(i % 7);
        k.fill = 0.01 * double(i % 5);
        s.enclosure.set_factors(int(i), k);
    }
    return s;
}

void expect_equal(const Solved& a, const Solved& b) {
    ASSERT_EQ(a.h.nodes.size(), b.h.nodes.size());
    int64_t diffs = 0;
    for (size_t i = 0; i < a.h.nodes.size(); ++i) {
        const Node &x = a.h.nodes[i], &y = b.h.nodes[i];
        bool ok = same(x.L, y.L) && same(x.Lmin, y.Lmin) && same(x.Lmax, y.Lmax);
        if (!x.dead && !x.in_links.empty()) ok = ok && same(x.G, y.G);
        if (x.is_cluster())
            for (int k = 0; k < kBins; ++k) ok = ok && same(x.S[size_t(k)], y.S[size_t(k)]);
        diffs += !ok;
    }
    for (size_t i = 0; i < a.links.size(); ++i)
        if (a.links[i].active && a.h.nodes[size_t(a.links[i].rcv)].is_cluster())
            diffs += !same(a.links[i].value, b.links[i].value);
    EXPECT_EQ(diffs, 0) << "nodes or links that differ";
}

struct Case {
    const char* name;
    SceneDesc (*scene)();
    double eps;
    bool clustering;
};
void PrintTo(const Case& c, std::ostream* os) { *os << c.name; }

class GatherPlanTest : public ::testing::TestWithParam<Case> {};

}  // namespace

TEST_P(GatherPlanTest, SweepsAreBitIdenticalToASweepOverTheHierarchy) {
    const Case& c = GetParam();
    const Solved start = solved(c.scene(), c.eps, c.clustering);
    // A direct-light term that differs from leaf to leaf (lights.cpp's role).
    const Direct direct = [](int id) { return Rgb{0.001 * (id % 3), 0.002 * (id % 5), 0.0}; };
    Solved ref = start, got = start;
    ReferenceSweep reference{ref.h, ref.links, ref.enclosure, direct};
    GatherPlan plan;
    plan.build(got.h, got.links, 2);
    plan.prepare_radiometry(got.h, got.links, got.enclosure, direct, 2);
    EXPECT_EQ(plan.link_count(), [&] {
        int64_t n = 0;
        for (const Node& q : start.h.nodes) n += q.dead ? 0 : int64_t(q.in_links.size());
        return n;
    }());
    for (int k = 0; k < 4; ++k) {
        const double d_ref = reference.sweep(false, nullptr);
        const double d_got = plan.sweep(false, nullptr, 2);
        EXPECT_EQ(d_ref, d_got) << "sweep " << k;
        EXPECT_GT(d_got, 0.0);
    }
    plan.write_back(got.h, got.links, 2);
    expect_equal(ref, got);

    // The unit sweep (closure correction): the coupling sums of every leaf, from a plan...
    auto fresh = [&] {
        CouplingSums c;
        c.total.assign(start.h.nodes.size(), -1.0);
        c.own.assign(start.h.nodes.size(), -1.0);
        return c;
    };
    auto same = [](const std::vector<double>& a, const std::vector<double>& b) {
        return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
    };
    CouplingSums f_ref = fresh(), f_got = fresh();
    ReferenceSweep{ref.h, ref.links, ref.enclosure, direct}.sweep(true, &f_ref);
    GatherPlan unit_plan;
    unit_plan.build(got.h, got.links, 1);
    EXPECT_FALSE(unit_plan.has_radiometry());
    EXPECT_EQ(unit_plan.sweep(true, &f_got, 1), 0.0);
    EXPECT_TRUE(same(f_ref.total, f_got.total));
    EXPECT_TRUE(same(f_ref.own, f_got.own));
    // ... and straight from the hierarchy, without a plan.
    CouplingSums f_direct = fresh();
    coupling_sums(got.h, got.links, f_direct, 2);
    EXPECT_TRUE(same(f_ref.total, f_direct.total));
    EXPECT_TRUE(same(f_ref.own, f_direct.own));
    int leaves = 0, with_own = 0, with_inherited = 0;
    for (size_t i = 0; i < f_got.total.size(); ++i) {
        if (f_got.total[i] < 0) continue;
        ++leaves;
        with_own += f_got.own[i] > 0;
        with_inherited += f_got.total[i] > f_got.own[i];
    }
    EXPECT_GT(leaves, 0);
    EXPECT_GT(with_own, 0);        // both parts occur, so the test tells them apart
    EXPECT_GT(with_inherited, 0);
}

INSTANTIATE_TEST_SUITE_P(Scenes, GatherPlanTest,
                         ::testing::Values(Case{"box_room", [] { return scenes::box_room(4); }, 0.1, true},
                                           Case{"cornell_unclustered", [] { return scenes::cornell_box(2); }, 0.2, false},
                                           Case{"furnace", [] { return scenes::furnace_cube(0.8, 1.0, 3); }, 0.1, true}),
                         [](const ::testing::TestParamInfo<Case>& i) { return std::string(i.param.name); });

TEST(GatherPlan, IsStaleOnceLinksOrNodesWereAddedOrItWasInvalidated) {
    Solved s = solved(scenes::box_room(2), 0.2, true);
    GatherPlan plan;
    EXPECT_FALSE(plan.valid(s.links.size(), s.h.nodes.size()));
    plan.build(s.h, s.links, 1);
    EXPECT_TRUE(plan.valid(s.links.size(), s.h.nodes.size()));
    EXPECT_FALSE(plan.valid(s.links.size() + 1, s.h.nodes.size()));
    EXPECT_FALSE(plan.valid(s.links.size(), s.h.nodes.size() + 4));
    plan.invalidate();
    EXPECT_FALSE(plan.valid(s.links.size(), s.h.nodes.size()));
}

TEST(GatherPlan, WriteBackWithoutASweepChangesNothing) {
    Solved s = solved(scenes::box_room(2), 0.2, true);
    Solved before = s;
    GatherPlan plan;
    plan.build(s.h, s.links, 1);
    plan.prepare_radiometry(s.h, s.links, s.enclosure, [](int) { return Rgb{}; }, 1);
    CouplingSums sums;
    sums.reset(s.h.nodes.size());
    plan.sweep(true, &sums, 1);  // a unit sweep leaves the radiometry alone
    plan.write_back(s.h, s.links, 1);
    expect_equal(before, s);
}
