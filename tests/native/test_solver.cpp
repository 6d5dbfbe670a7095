#include <gtest/gtest.h>
#include "radiosity/builtin_scenes.h"
#include "radiosity/solver.h"
using namespace radiosity;
TEST(Furnace, Cube) {
    Solver s(scenes::furnace_cube(0.5, 1.0, 4), Settings::preset("MEDIUM"));
    s.solve();
    auto c = s.corner_radiance(0);
    for (float v : c) EXPECT_NEAR(v, 2.0, 0.002);
}
