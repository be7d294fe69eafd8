#include "processes/tracker/feature_tracker.h"
#include <gtest/gtest.h>
#include <opencv2/video/tracking.hpp>
#include <opencv2/imgproc.hpp>
#include <cstdio>
#include <ctime>
static int64_t cpu_ticks(){ timespec t; clock_gettime(CLOCK_THREAD_CPUTIME_ID,&t); return (int64_t)t.tv_sec*1000000000LL+t.tv_nsec; }
#include "synthetic_scene.h"
using namespace nadir;
using namespace nadir::testing;
const cv::Size kFrame(612, 512);
TEST(Dbg, Timing) {
  cv::setNumThreads(1);
  static const SyntheticScene s(cv::Size(1400, 1400), 42);
  cv::Mat a = s.render({{700, 700}, 0}, kFrame, 1.5, 1), b = s.render({{702.8, 701.2}, 0.0035}, kFrame, 1.5, 2);
  FeatureTracker tr{TrackerOptions{}};
  tr.process(a);
  std::vector<cv::Point2f> pts; for (auto& f : tr.features()) pts.push_back(f.px);
  std::vector<cv::Mat> pa, pb;
  const int N = 50;
  auto t0 = cpu_ticks();
  for (int i = 0; i < N; ++i) cv::buildOpticalFlowPyramid(a, pa, cv::Size(21,21), 2, true, cv::BORDER_REFLECT_101, cv::BORDER_CONSTANT, false);
  auto t1 = cpu_ticks();
  cv::buildOpticalFlowPyramid(b, pb, cv::Size(21,21), 2, true, cv::BORDER_REFLECT_101, cv::BORDER_CONSTANT, false);
  std::vector<cv::Point2f> out, back; std::vector<uchar> st; std::vector<float> err;
  for (int eps_i = 0; eps_i < 3; ++eps_i) {
    double eps = eps_i == 0 ? 0.01 : eps_i == 1 ? 0.03 : 0.1; int its = eps_i == 0 ? 30 : eps_i == 1 ? 20 : 10;
    auto t2 = cpu_ticks();
    for (int i = 0; i < N; ++i) cv::calcOpticalFlowPyrLK(pa, pb, pts, out, st, err, cv::Size(21,21), 2, cv::TermCriteria(3, its, eps), 0, 1e-4);
    auto t3 = cpu_ticks();
    for (int i = 0; i < N; ++i) { back = pts; cv::calcOpticalFlowPyrLK(pb, pa, out, back, st, err, cv::Size(21,21), 2, cv::TermCriteria(3, its, eps), cv::OPTFLOW_USE_INITIAL_FLOW, 1e-4); }
    auto t4 = cpu_ticks();
    printf("eps %.2f its %d fwd %.3f ms bwd %.3f ms\n", eps, its, (t3-t2)/1e9*1e3/N, (t4-t3)/1e9*1e3/N);
  }
  printf("pyr %.3f ms\n", (t1-t0)/1e9*1e3/N);
  cv::Mat resp;
  auto t5 = cpu_ticks();
  for (int i = 0; i < N; ++i) cv::cornerHarris(a(cv::Rect(10,10,194,160)), resp, 3, 3, 0.04);
  auto t6 = cpu_ticks();
  printf("harris cell %.3f ms\n", (t6-t5)/1e9*1e3/N);
  auto t7 = cpu_ticks();
  for (int i = 0; i < N; ++i) { FeatureTracker t2{TrackerOptions{}}; t2.process(a); }
  auto t8 = cpu_ticks();
  printf("first frame %.3f ms\n", (t8-t7)/1e9*1e3/N);
}
