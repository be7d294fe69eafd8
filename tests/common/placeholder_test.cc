#include <gtest/gtest.h>
#include "common/time_base.h"
TEST(TimeBase, RoundTrip) { EXPECT_EQ(nadir::s_to_us(1.5), 1500000); }
