// Visibility: objects never moved share one Embree scene; a placement moves an object into a
// scene of its own. Rays, hit objects and triangle indices must not tell the two apart.
#include <gtest/gtest.h>

#include <vector>

#include "radiosity/visibility.h"

using namespace radiosity;

namespace {

// An axis-aligned square in the plane x = x0, centred at (x0, y, z), side 2 h, as four
// triangles fanned from its centre: 0 the quarter toward -z, 1 toward +y, 2 toward +z, 3
// toward -y.
std::vector<Vec3> wall(double x0, double y, double z, double h) {
    std::vector<Vec3> t;
    const Vec3 a{x0, y - h, z - h}, b{x0, y + h, z - h}, c{x0, y + h, z + h}, d{x0, y - h, z + h}, m{x0, y, z};
    t.insert(t.end(), {a, b, m});
    t.insert(t.end(), {b, c, m});
    t.insert(t.end(), {c, d, m});
    t.insert(t.end(), {d, a, m});
    return t;
}

Rigid shift(Vec3 t) {
    Rigid r;
    r.t = t;
    return r;
}

}  // namespace

TEST(Visibility, SharedAndMovedObjectsAreHitAlike) {
    Visibility v;
    v.add_object(0, wall(1, 0, 0, 1));
    v.add_object(1, {});  // no triangle: nothing to hit
    v.add_object(2, wall(3, 0, 0, 1));
    v.commit();
    Vec3 hit;
    int tri = -1;
    EXPECT_EQ(v.hit_object({0, 0, 0.5}, {5, 0, 0.5}, 0, &hit, &tri), 0);
    EXPECT_NEAR(hit.x, 1.0, 1e-6);
    EXPECT_EQ(tri, 2);
    EXPECT_TRUE(v.occluded({0, 0, 0.5}, {5, 0, 0.5}));
    EXPECT_FALSE(v.occluded({0, 0, 0.5}, {0.9, 0, 0.5}));

    // The near wall moved 4 up: the ray meets the far wall; the moved wall is hit where it went,
    // with the same triangle indices.
    v.set_object_transform(0, shift({0, 4, 0}));
    v.commit();
    EXPECT_EQ(v.hit_object({0, 0, 0.5}, {5, 0, 0.5}, 0, &hit, &tri), 2);
    EXPECT_NEAR(hit.x, 3.0, 1e-6);
    EXPECT_EQ(tri, 2);
    EXPECT_EQ(v.hit_object({0, 4, -0.5}, {5, 4, -0.5}, 0, &hit, &tri), 0);
    EXPECT_NEAR(hit.x, 1.0, 1e-6);
    EXPECT_EQ(tri, 0);

    // Back where it was given: hit there again (now through its own scene).
    v.set_object_transform(0, Rigid{});
    v.commit();
    EXPECT_EQ(v.hit_object({0, 0, 0.5}, {5, 0, 0.5}, 0, &hit, &tri), 0);
    EXPECT_FALSE(v.occluded({0, 4, -0.5}, {5, 4, -0.5}));

    // Removed, from the shared scene and from its own: rays pass.
    v.remove_object(2);
    v.remove_object(0);
    v.commit();
    EXPECT_EQ(v.hit_object({0, 0, 0.5}, {5, 0, 0.5}, 0, &hit), -1);
    EXPECT_FALSE(v.occluded({0, 0, 0.5}, {5, 0, 0.5}));
}

TEST(Visibility, ObjectsPlacedBeforeTheFirstCommitAndManyObjects) {
    // A row of small walls, every third placed (moved 10 along y) before the first commit, as a
    // full solve places objects moved earlier; then two more moved after it.
    Visibility v;
    const int n = 30;
    for (int i = 0; i < n; ++i) v.add_object(i, wall(1.0 + i, 0, 3.0 * i, 0.5));
    for (int i = 0; i < n; i += 3) v.set_object_transform(i, shift({0, 10, 0}));
    v.commit();
    auto check = [&](const char* when, const std::vector<int>& moved) {
        for (int i = 0; i < n; ++i) {
            bool m = false;
            for (int k : moved) m = m || k == i;
            const double y = m ? 10.0 : 0.0;
            Vec3 hit;
            int tri = -1;
            EXPECT_EQ(v.hit_object({0, y + 0.2, 3.0 * i + 0.1}, {100, y + 0.2, 3.0 * i + 0.1}, 0, &hit, &tri), i)
                << when << " object " << i;
            EXPECT_NEAR(hit.x, 1.0 + i, 1e-5) << when << " object " << i;
            EXPECT_EQ(tri, 1) << when << " object " << i;
            EXPECT_FALSE(v.occluded({0, 10.0 - y + 0.2, 3.0 * i + 0.1}, {100, 10.0 - y + 0.2, 3.0 * i + 0.1}))
                << when << " object " << i;
        }
    };
    std::vector<int> moved;
    for (int i = 0; i < n; i += 3) moved.push_back(i);
    check("placed before the first commit", moved);
    v.set_object_transform(1, shift({0, 10, 0}));
    v.set_object_transform(4, shift({0, 10, 0}));
    v.commit();
    moved.push_back(1);
    moved.push_back(4);
    check("two more moved", moved);
}
