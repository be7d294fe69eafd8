#include "processes/tracker/feature_tracker.h"
#include <gtest/gtest.h>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include "synthetic_scene.h"
using namespace nadir;
using namespace nadir::testing;
const cv::Size kFrame(612, 512);
TEST(Dbg, Rot) {
  static const SyntheticScene s(cv::Size(1600, 1600), 42);
  for (double deg : {0.2, 1.0, 2.0, 3.0}) {
    FeatureTracker tracker{TrackerOptions{}};
    const ViewPose a{{800, 800}, 0.0};
    const ViewPose b{{803.0, 798.0}, deg * M_PI / 180};
    tracker.process(s.render(a, kFrame));
    auto step = tracker.process(s.render(b, kFrame));
    std::vector<double> e;
    for (auto& t : step.tracks) {
      auto x = SyntheticScene::map_point(t.prev_px, a, b, kFrame);
      e.push_back(std::hypot(t.curr_px.x - x.x, t.curr_px.y - x.y));
    }
    std::sort(e.begin(), e.end());
    printf("deg %.1f n %zu med %.3f p95 %.3f max %.3f\n", deg, e.size(), e[e.size()/2], e[e.size()*95/100], e.back());
  }
  std::map<int,int> cells;
  FeatureTracker tracker{TrackerOptions{}};
  tracker.process(s.render({{800, 800}, 0.0}, kFrame));
  GridCornerDetector g{TrackerOptions{}};
  for (auto& f : tracker.features()) cells[g.cell_index(kFrame, f.px)]++;
  for (auto& [c, n] : cells) printf("cell %d: %d\n", c, n);
}
TEST(Dbg, Occ) {
  static const SyntheticScene s(cv::Size(1600, 1600), 42);
  const ViewPose a{{800, 800}, 0.0};
  const ViewPose b{{803.0, 802.0}, 0.0};
  const cv::Mat first = s.render(a, kFrame);
  const cv::Rect box(230, 190, 150, 130);
  cv::Mat second = s.render(b, kFrame);
  const SyntheticScene other(cv::Size(box.width, box.height), 777);
  other.texture().copyTo(second(box));
  FeatureTracker tracker{TrackerOptions{}};
  tracker.process(first);
  auto step = tracker.process(second);
  for (auto& t : step.tracks) {
    auto x = SyntheticScene::map_point(t.prev_px, a, b, kFrame);
    double e = std::hypot(t.curr_px.x - x.x, t.curr_px.y - x.y);
    if (e > 0.3) printf("prev (%.1f,%.1f) curr (%.2f,%.2f) exp (%.2f,%.2f) err %.2f\n", t.prev_px.x, t.prev_px.y, t.curr_px.x, t.curr_px.y, x.x, x.y, e);
  }
  printf("fb %d lost %d\n", step.fb_rejected, step.klt_lost);
}
