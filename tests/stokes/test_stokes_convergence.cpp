#include <gtest/gtest.h>
TEST(StokesConvergence, Placeholder) {}
