// The solved heading change against the INS heading change: a rotated photo
// trips the bound, ordinary pairs and turns across +-180 deg do not.

#include <gtest/gtest.h>

#include <cmath>

#include "common/geometry.h"
#include "processes/vo_solver/heading_check.h"

namespace nadir::vo {
namespace {

HeadingCheckOptions bound_deg(double deg) {
  HeadingCheckOptions o;
  o.max_dyaw_vs_ins_rad = deg_to_rad(deg);
  return o;
}

TEST(HeadingCheck, DefaultBoundIsTwentyDegrees) {
  EXPECT_NEAR(rad_to_deg(HeadingCheckOptions{}.max_dyaw_vs_ins_rad), 20.0, 1e-12);
}

TEST(HeadingCheck, AgreeingPairsPass) {
  const HeadingCheckOptions o;
  EXPECT_FALSE(heading_contradicts_ins(deg_to_rad(3.0), deg_to_rad(10.0), deg_to_rad(12.0), o));
  // A half turn between photos: the INS change is +-180 deg, the solve -179.5 deg.
  EXPECT_FALSE(heading_contradicts_ins(deg_to_rad(-179.5), deg_to_rad(30.0), deg_to_rad(-150.0), o));
  // Across the +-180 deg seam of the INS yaw.
  EXPECT_FALSE(heading_contradicts_ins(deg_to_rad(4.0), deg_to_rad(178.0), deg_to_rad(-178.0), o));
  EXPECT_FALSE(heading_contradicts_ins(deg_to_rad(19.9), 0.0, 0.0, o));
}

TEST(HeadingCheck, RotatedPhotoAndWrongTurnTrip) {
  const HeadingCheckOptions o;
  EXPECT_TRUE(heading_contradicts_ins(M_PI, 0.0, 0.0, o));                                 // saved rotated 180 deg
  EXPECT_TRUE(heading_contradicts_ins(deg_to_rad(92.0), deg_to_rad(5.0), deg_to_rad(3.0), o));  // 90 deg
  EXPECT_TRUE(heading_contradicts_ins(deg_to_rad(-25.0), deg_to_rad(40.0), deg_to_rad(40.0), o));
  EXPECT_TRUE(heading_contradicts_ins(std::nan(""), 0.0, 0.0, o)) << "no heading change is no agreement";
}

TEST(HeadingCheck, BoundIsTheOptionAndZeroTurnsItOff) {
  EXPECT_TRUE(heading_contradicts_ins(deg_to_rad(6.0), 0.0, 0.0, bound_deg(5.0)));
  EXPECT_FALSE(heading_contradicts_ins(deg_to_rad(4.0), 0.0, 0.0, bound_deg(5.0)));
  EXPECT_FALSE(heading_contradicts_ins(M_PI, 0.0, 0.0, bound_deg(0.0)));
}

}  // namespace
}  // namespace nadir::vo
