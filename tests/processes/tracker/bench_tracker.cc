// Tracker timing on one core: 612x512 frames, 450 features, frame-to-frame
// motion like the paper's flights (about 3 px and 0.2 deg per frame at 14 Hz,
// 150-300 m above ground) plus 1.5 grey levels of pixel noise.
//   BM_FeatureTracker: the algorithm (pyramid, KLT forward+backward, replenish)
//   BM_TrackerNode:    the whole image_t -> tracks_t path (checks, undistortion,
//                      LCM encoding) minus the transport.
//   BM_DescriptorMatcher: tracker.mode descriptor, per frame (keypoints,
//                      descriptors, matching, RANSAC) for orb, akaze, sift at
//                      612x512 and 1000x562 on a survey-like sequence.
//   BM_Klt*, BM_Pyramid*: one KLT pass (450 corners, 21x21, 3 levels, from
//                      their own position) and one pyramid, OpenCV's against
//                      lucas_kanade.h's, on a pair of frames.
// Each on two image sources: `synthetic` (a generated texture, above) and
// `sim_test1` (the simulator's renderer along the test1 profile: what replay
// of a simulated flight costs; its terrain texture makes KLT work harder).
#include <benchmark/benchmark.h>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

#include <cmath>
#include <string>
#include <vector>

#include "common/bus.h"
#include "common/config.h"
#include "processes/sim/flight_profile.h"
#include "processes/sim/renderer.h"
#include "processes/sim/sim_camera.h"
#include "processes/tracker/descriptor_matcher.h"
#include "processes/tracker/feature_tracker.h"
#include "processes/tracker/lucas_kanade.h"
#include "processes/tracker/tracker_node.h"
#include "synthetic_scene.h"

namespace {

using nadir::testing::SyntheticScene;
using nadir::testing::ViewPose;

constexpr int kFrames = 40;

// A sequence that flies forward and back so looping it keeps the motion smooth.
const std::vector<cv::Mat>& frames() {
  static const std::vector<cv::Mat> sequence = [] {
    const SyntheticScene scene(cv::Size(1400, 1400), 11);
    std::vector<cv::Mat> out;
    for (int k = 0; k < kFrames; ++k) {
      const ViewPose pose{{500 + 2.8 * k, 600 + 1.2 * k}, 0.0035 * k};
      out.push_back(scene.render(pose, cv::Size(612, 512), 1.5, 1000 + k));
    }
    for (int k = kFrames - 2; k > 0; --k) out.push_back(out[static_cast<size_t>(k)]);
    return out;
  }();
  return sequence;
}

// 40 frames of the simulator along test1 from t = 100 s at the camera rate,
// then back, like frames().
const std::vector<cv::Mat>& sim_frames() {
  static const std::vector<cv::Mat> sequence = [] {
    cv::setNumThreads(1);
    const std::string root = NADIR_SOURCE_DIR;
    const auto camera = nadir::sim::SimCamera::from_config(nadir::Config::load_file(root + "/config/default.yaml"));
    const auto profile = nadir::sim::FlightProfile::load(root + "/config/profiles/test1.yaml");
    nadir::sim::TerrainOptions terrain_options = profile.terrain;
    terrain_options.seed = 101;  // the terrain of table1.sh's test1 flight
    const nadir::sim::Terrain terrain(terrain_options);
    const nadir::sim::Trajectory trajectory(profile, 101);
    nadir::sim::Renderer renderer(camera, terrain, nadir::sim::RendererOptions{});
    std::vector<cv::Mat> out;
    std::vector<uint8_t> image;
    for (int k = 0; k < kFrames; ++k) {
      const nadir::sim::TruthState s = trajectory.at(100.0 + k / camera.rate_hz);
      renderer.render(s.position_ned, s.world_from_body() * camera.body_from_camera, static_cast<uint64_t>(k), &image);
      out.push_back(cv::Mat(camera.height, camera.width, CV_8UC1, image.data()).clone());
    }
    for (int k = kFrames - 2; k > 0; --k) out.push_back(out[static_cast<size_t>(k)]);
    return out;
  }();
  return sequence;
}

using FrameSource = const std::vector<cv::Mat>& (*)();

// Arguments: pyramid levels of the backward (forward-backward check) pass;
// 1 for the window warp (klt_window_warp, with the default camera's lens),
// 2 for it with the local warp (klt_local_warp).
void BM_FeatureTracker(benchmark::State& state, FrameSource source) {
  cv::setNumThreads(1);
  const auto& seq = source();
  nadir::TrackerOptions options;
  options.fb_pyramid_levels = static_cast<int>(state.range(0));
  options.klt_window_warp = state.range(1) != 0;
  options.klt_local_warp = state.range(1) == 2;
  const nadir::CameraModel lens =
      nadir::CameraModel::from_config(nadir::Config::load_file(NADIR_SOURCE_DIR "/config/default.yaml"));
  nadir::FeatureTracker tracker{options, &lens};
  size_t k = 0;
  int64_t tracks = 0, replenished = 0, steps = 0;
  tracker.process(seq[k++]);
  for (auto _ : state) {
    const nadir::TrackStepResult r = tracker.process(seq[k++ % seq.size()]);
    tracks += static_cast<int64_t>(r.tracks.size());
    replenished += r.replenished;
    ++steps;
  }
  state.counters["tracks"] = static_cast<double>(tracks) / static_cast<double>(steps);
  state.counters["new_per_frame"] = static_cast<double>(replenished) / static_cast<double>(steps);
}
BENCHMARK_CAPTURE(BM_FeatureTracker, synthetic, frames)
    ->Args({1, 0})
    ->Args({2, 0})
    ->Args({3, 0})
    ->Args({2, 1})
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_FeatureTracker, sim_test1, sim_frames)
    ->Args({2, 0})
    ->Args({2, 1})
    ->Args({2, 2})
    ->Unit(benchmark::kMillisecond);

// Counts what the node publishes; the transport is not what is measured.
class SinkBus : public nadir::Bus {
 public:
  void publish_raw(const std::string&, const uint8_t*, size_t size) override { bytes += static_cast<int64_t>(size); }
  void subscribe_raw(const std::string&, RawHandler) override {}
  int64_t bytes = 0;
};

void BM_TrackerNode(benchmark::State& state, FrameSource source) {
  cv::setNumThreads(1);
  const auto& seq = source();
  std::vector<nadir::image_t> images;
  for (size_t k = 0; k < seq.size(); ++k) images.push_back(nadir::testing::make_image_msg(seq[k], 0, 0));
  const nadir::Config config = nadir::Config::load_file(NADIR_SOURCE_DIR "/config/default.yaml");
  SinkBus bus;
  nadir::TrackerNode node(config, bus);
  int64_t utime = 1700000000000000, counter = 0;
  for (auto _ : state) {
    nadir::image_t& msg = images[static_cast<size_t>(counter) % images.size()];
    msg.utime = utime;
    msg.frame_counter = counter;
    node.on_image(msg);
    utime += 71429;
    ++counter;
  }
  state.counters["kB_out_per_frame"] = static_cast<double>(bus.bytes) / 1024.0 / static_cast<double>(counter);
}
BENCHMARK_CAPTURE(BM_TrackerNode, synthetic, frames)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_TrackerNode, sim_test1, sim_frames)->Unit(benchmark::kMillisecond);

// 450 corners of frame 0 of `source`, tracked into frame 1.
struct KltJob {
  cv::Mat prev, curr;
  std::vector<cv::Point2f> points;
};

KltJob klt_job(FrameSource source) {
  KltJob job{source()[0], source()[1], {}};
  cv::goodFeaturesToTrack(job.prev, job.points, 450, 0.01, 10, cv::noArray(), 3, true, 0.04);
  return job;
}

const cv::TermCriteria kCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 30, 0.01);

void BM_KltOpenCv(benchmark::State& state, FrameSource source) {
  cv::setNumThreads(1);
  const KltJob job = klt_job(source);
  std::vector<cv::Mat> prev, curr;
  cv::buildOpticalFlowPyramid(job.prev, prev, cv::Size(21, 21), 2, true);
  cv::buildOpticalFlowPyramid(job.curr, curr, cv::Size(21, 21), 2, true);
  std::vector<cv::Point2f> next;
  std::vector<uchar> status;
  std::vector<float> error;
  for (auto _ : state) {
    cv::calcOpticalFlowPyrLK(prev, curr, job.points, next, status, error, cv::Size(21, 21), 2, kCriteria, 0, 1e-4);
    benchmark::DoNotOptimize(next.data());
  }
}
BENCHMARK_CAPTURE(BM_KltOpenCv, sim_test1, sim_frames)->Unit(benchmark::kMillisecond);

void BM_KltNadir(benchmark::State& state, FrameSource source) {
  const KltJob job = klt_job(source);
  const int border = nadir::LucasKanade::border_for(21);
  nadir::LkPyramid prev, curr;
  prev.build(job.prev, 3, border);
  curr.build(job.curr, 3, border);
  nadir::LucasKanade klt{nadir::LkOptions{}};
  std::vector<cv::Point2f> next(job.points.size());
  std::vector<float> error(job.points.size());
  for (auto _ : state) {
    for (size_t i = 0; i < job.points.size(); ++i) {
      next[i] = job.points[i];
      klt.track(prev, curr, job.points[i], &next[i], 2, &error[i]);
    }
    benchmark::DoNotOptimize(next.data());
  }
}
BENCHMARK_CAPTURE(BM_KltNadir, sim_test1, sim_frames)->Unit(benchmark::kMillisecond);

void BM_PyramidOpenCv(benchmark::State& state, FrameSource source) {
  cv::setNumThreads(1);
  const cv::Mat image = source()[0];
  std::vector<cv::Mat> pyramid;
  for (auto _ : state) cv::buildOpticalFlowPyramid(image, pyramid, cv::Size(21, 21), 2, true, cv::BORDER_REFLECT_101,
                                                   cv::BORDER_CONSTANT, false);
}
BENCHMARK_CAPTURE(BM_PyramidOpenCv, sim_test1, sim_frames)->Unit(benchmark::kMicrosecond);

void BM_PyramidNadir(benchmark::State& state, FrameSource source) {
  cv::setNumThreads(1);
  const cv::Mat image = source()[0];
  nadir::LkPyramid pyramid;
  for (auto _ : state) pyramid.build(image, 3, nadir::LucasKanade::border_for(21));
}
BENCHMARK_CAPTURE(BM_PyramidNadir, sim_test1, sim_frames)->Unit(benchmark::kMicrosecond);

// Photos of a survey: the view circles the scene (radius a third of the frame
// width) turning 45 degrees a frame, so consecutive frames overlap 60-70 %
// and the sequence loops.
std::vector<cv::Mat> survey_frames(cv::Size size) {
  static const SyntheticScene scene(cv::Size(2200, 2200), 17);
  std::vector<cv::Mat> out;
  for (int k = 0; k < 8; ++k) {
    const double a = k * CV_PI / 4.0;
    const ViewPose pose{{1100 + size.width / 3.0 * std::cos(a), 1100 + size.width / 3.0 * std::sin(a)}, a};
    out.push_back(scene.render(pose, size, 1.5, 300 + k));
  }
  return out;
}

void BM_DescriptorMatcher(benchmark::State& state) {
  cv::setNumThreads(1);
  const char* types[] = {"orb", "akaze", "sift"};
  const cv::Size size = state.range(1) == 0 ? cv::Size(612, 512) : cv::Size(1000, 562);
  const std::vector<cv::Mat> sequence = survey_frames(size);
  nadir::CameraModel camera;
  camera.width = size.width;
  camera.height = size.height;
  camera.fx = camera.fy = 0.8 * size.width;
  camera.cx = (size.width - 1) / 2.0;
  camera.cy = (size.height - 1) / 2.0;
  camera.distortion = {0, 0, 0, 0, 0};
  nadir::DescriptorOptions options;
  options.type = types[state.range(0)];
  nadir::DescriptorMatcher matcher(options, camera);
  size_t k = 0;
  int64_t tracks = 0, steps = 0;
  for (auto _ : state) {
    const nadir::TrackStepResult step = matcher.process(sequence[k++ % sequence.size()]);
    if (!step.first_frame) {
      tracks += static_cast<int64_t>(step.tracks.size());
      ++steps;
    }
  }
  state.SetLabel(std::string(options.type) + (state.range(1) == 0 ? " 612x512" : " 1000x562"));
  if (steps > 0) state.counters["tracks"] = static_cast<double>(tracks) / static_cast<double>(steps);
}
BENCHMARK(BM_DescriptorMatcher)->ArgsProduct({{0, 1, 2}, {0, 1}})->Unit(benchmark::kMillisecond);

}  // namespace
