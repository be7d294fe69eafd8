#include "processes/tracker/feature_tracker.h"
#include <gtest/gtest.h>
#include <cmath>
#include <cstdio>
#include "synthetic_scene.h"
using namespace nadir;
using namespace nadir::testing;
TEST(Dbg, Worst) {
  const cv::Size kFrame(612, 512);
  static const SyntheticScene s(cv::Size(1600, 1600), 42);
  for (int variant = 0; variant < 2; ++variant) {
    FeatureTracker tracker{TrackerOptions{}};
    const ViewPose a{{800, 800}, 0.0};
    const ViewPose b = variant == 0 ? ViewPose{{807.3, 795.4}, 0.0} : ViewPose{{803.0, 798.0}, 3.0 * M_PI / 180};
    tracker.process(s.render(a, kFrame));
    auto step = tracker.process(s.render(b, kFrame));
    for (auto& t : step.tracks) {
      auto e = SyntheticScene::map_point(t.prev_px, a, b, kFrame);
      double err = std::hypot(t.curr_px.x - e.x, t.curr_px.y - e.y);
      if (err > 0.3) printf("v%d id %ld prev (%.1f,%.1f) curr (%.2f,%.2f) exp (%.2f,%.2f) err %.2f\n", variant, (long)t.id, t.prev_px.x, t.prev_px.y, t.curr_px.x, t.curr_px.y, e.x, e.y, err);
    }
    printf("fb_rejected %d lost %d out %d tracks %zu\n", step.fb_rejected, step.klt_lost, step.out_of_image, step.tracks.size());
  }
}
