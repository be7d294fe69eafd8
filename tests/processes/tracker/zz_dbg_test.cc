#include "processes/tracker/feature_tracker.h"
#include <gtest/gtest.h>
#include <opencv2/video/tracking.hpp>
#include <opencv2/imgproc.hpp>
#include <cstdio>
#include <ctime>
#include "synthetic_scene.h"
static int64_t cpu_ticks(){ timespec t; clock_gettime(CLOCK_THREAD_CPUTIME_ID,&t); return (int64_t)t.tv_sec*1000000000LL+t.tv_nsec; }
using namespace nadir;
using namespace nadir::testing;
const cv::Size kFrame(612, 512);
TEST(Dbg, Occ) {
  cv::setNumThreads(1);
  static const SyntheticScene s(cv::Size(1600, 1600), 42);
  const ViewPose a{{800, 800}, 0.0};
  const ViewPose b{{803.0, 802.0}, 0.0};
  const cv::Mat first = s.render(a, kFrame);
  const cv::Rect box(230, 190, 150, 130);
  cv::Mat second = s.render(b, kFrame);
  const SyntheticScene other(cv::Size(box.width, box.height), 777);
  other.texture().copyTo(second(box));
  FeatureTracker tr{TrackerOptions{}};
  tr.process(first);
  std::vector<cv::Point2f> pts; for (auto& f : tr.features()) pts.push_back(f.px);
  std::vector<cv::Mat> pa, pb;
  cv::buildOpticalFlowPyramid(first, pa, cv::Size(21,21), 2, true, cv::BORDER_REFLECT_101, cv::BORDER_CONSTANT, false);
  cv::buildOpticalFlowPyramid(second, pb, cv::Size(21,21), 2, true, cv::BORDER_REFLECT_101, cv::BORDER_CONSTANT, false);
  std::vector<cv::Point2f> out, back; std::vector<uchar> st, st2; std::vector<float> err, err2;
  cv::calcOpticalFlowPyrLK(pa, pb, pts, out, st, err, cv::Size(21,21), 2, cv::TermCriteria(3, 30, 0.01), 0, 1e-4);
  for (int bl = 0; bl <= 2; ++bl) {
    back = pts;
    const int N = 30;
    auto t0 = cpu_ticks();
    for (int i = 0; i < N; ++i) { back = pts; cv::calcOpticalFlowPyrLK(pb, pa, out, back, st2, err2, cv::Size(21,21), bl, cv::TermCriteria(3, 30, 0.01), cv::OPTFLOW_USE_INITIAL_FLOW, 1e-4); }
    auto t1 = cpu_ticks();
    int bad_pass = 0, good_fail = 0, good = 0;
    for (size_t i = 0; i < pts.size(); ++i) {
      auto x = SyntheticScene::map_point(pts[i], a, b, kFrame);
      bool wrong = std::hypot(out[i].x - x.x, out[i].y - x.y) > 0.5;
      bool pass = st[i] && st2[i] && std::hypot(back[i].x - pts[i].x, back[i].y - pts[i].y) <= 1.0;
      if (wrong && pass) { bad_pass++; printf("  wrong passes: (%.0f,%.0f) err %.1f fwd-err %.2f\n", pts[i].x, pts[i].y, std::hypot(out[i].x - x.x, out[i].y - x.y), err[i]); }
      if (!wrong && !pass) good_fail++;
      if (!wrong) good++;
    }
    printf("bwd levels %d: %.3f ms, wrong-but-passed %d, right-but-rejected %d (right %d)\n", bl+1, (t1-t0)/1e6/N, bad_pass, good_fail, good);
  }
  std::vector<float> errs; for (size_t i = 0; i < pts.size(); ++i) if (st[i]) errs.push_back(err[i]);
  std::sort(errs.begin(), errs.end()); printf("fwd err median %.2f p90 %.2f p99 %.2f max %.2f\n", errs[errs.size()/2], errs[errs.size()*9/10], errs[errs.size()*99/100], errs.back());
}
