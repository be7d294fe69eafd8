// Tracker timing on one core: 612x512 frames, 450 features, frame-to-frame
// motion like the paper's flights (about 3 px and 0.2 deg per frame at 14 Hz,
// 150-300 m above ground) plus 1.5 grey levels of pixel noise.
//   BM_FeatureTracker: the algorithm (pyramid, KLT forward+backward, replenish)
//   BM_TrackerNode:    the whole image_t -> tracks_t path (checks, undistortion,
//                      LCM encoding) minus the transport.
#include <benchmark/benchmark.h>
#include <opencv2/core.hpp>

#include <vector>

#include "common/bus.h"
#include "processes/tracker/feature_tracker.h"
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

// Argument: pyramid levels of the backward (forward-backward check) pass.
void BM_FeatureTracker(benchmark::State& state) {
  cv::setNumThreads(1);
  const auto& seq = frames();
  nadir::TrackerOptions options;
  options.fb_pyramid_levels = static_cast<int>(state.range(0));
  nadir::FeatureTracker tracker{options};
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
BENCHMARK(BM_FeatureTracker)->Arg(1)->Arg(2)->Arg(3)->Unit(benchmark::kMillisecond);

// Counts what the node publishes; the transport is not what is measured.
class SinkBus : public nadir::Bus {
 public:
  void publish_raw(const std::string&, const uint8_t*, size_t size) override { bytes += static_cast<int64_t>(size); }
  void subscribe_raw(const std::string&, RawHandler) override {}
  int64_t bytes = 0;
};

void BM_TrackerNode(benchmark::State& state) {
  cv::setNumThreads(1);
  const auto& seq = frames();
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
BENCHMARK(BM_TrackerNode)->Unit(benchmark::kMillisecond);

}  // namespace
