#include <gtest/gtest.h>
#include "radiosity/geometry.h"
TEST(Smoke, Compiles) { EXPECT_TRUE(true); }
