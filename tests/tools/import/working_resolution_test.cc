// The working resolution's rule (docs/own-flight.md, "The working
// resolution"): the smallest whole factor that brings the long side to at
// most kWorkingLongSidePx, never up; --scale overrides.
#include <gtest/gtest.h>

#include "tools/import/working_resolution.h"

namespace nadir::import {
namespace {

void expect_resolution(int w, int h, double requested, double scale, int out_w, int out_h, const std::string& rule) {
  const WorkingResolution r = working_resolution(w, h, requested);
  EXPECT_DOUBLE_EQ(r.scale, scale) << w << "x" << h;
  EXPECT_EQ(r.width, out_w) << w << "x" << h;
  EXPECT_EQ(r.height, out_h) << w << "x" << h;
  EXPECT_EQ(r.rule, rule) << w << "x" << h;
}

TEST(WorkingResolution, TheDocumentedScales) {
  EXPECT_EQ(kWorkingLongSidePx, 1000);
  expect_resolution(4000, 3000, 0.0, 0.25, 1000, 750, "1/4: long side 4000 px over 1000 px");  // DJI Phantom 3, 12 MP
  expect_resolution(3000, 4000, 0.0, 0.25, 750, 1000, "1/4: long side 4000 px over 1000 px");  // portrait
  expect_resolution(4000, 2250, 0.0, 0.25, 1000, 563, "1/4: long side 4000 px over 1000 px");  // its 16:9 mode
  expect_resolution(5472, 3648, 0.0, 1.0 / 6, 912, 608, "1/6: long side 5472 px over 1000 px");  // 1" 20 MP
  expect_resolution(8000, 6000, 0.0, 0.125, 1000, 750, "1/8: long side 8000 px over 1000 px");  // 48 MP
  expect_resolution(1920, 1080, 0.0, 0.5, 960, 540, "1/2: long side 1920 px over 1000 px");    // HD video
  expect_resolution(1200, 900, 0.0, 0.5, 600, 450, "1/2: long side 1200 px over 1000 px");     // Seneca
  expect_resolution(1001, 700, 0.0, 0.5, 501, 350, "1/2: long side 1001 px over 1000 px");
  expect_resolution(1000, 750, 0.0, 1.0, 1000, 750, "1: long side 1000 px within 1000 px");
  expect_resolution(640, 512, 0.0, 1.0, 640, 512, "1: long side 640 px within 1000 px");  // thermal: never up
  expect_resolution(612, 512, 0.0, 1.0, 612, 512, "1: long side 612 px within 1000 px");  // the live camera
}

TEST(WorkingResolution, ScaleOverrides) {
  expect_resolution(4000, 3000, 1.0, 1.0, 4000, 3000, "1: --scale");
  expect_resolution(4000, 3000, 0.5, 0.5, 2000, 1500, "0.5: --scale");
  expect_resolution(640, 512, 0.25, 0.25, 160, 128, "0.25: --scale");
  EXPECT_THROW(working_resolution(0, 3000, 0.0), std::invalid_argument);
}

}  // namespace
}  // namespace nadir::import
