// The tracker node over a real LCM bus (memq://): images in, TRACKS out,
// bad and out-of-order input flagged and counted, byte-identical reruns.
#include "processes/tracker/tracker_node.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

#include "common/camera_model.h"
#include "common/channels.h"
#include "common/lcm_bus.h"
#include "synthetic_scene.h"

namespace nadir {
namespace {

using testing::make_image_msg;
using testing::SyntheticScene;
using testing::ViewPose;

const cv::Size kFrame(612, 512);
constexpr int64_t kPeriodUs = 71429;  // 14 Hz, as in config/default.yaml
constexpr int64_t kStartUs = 1700000000000000;

Config default_config() { return Config::load_file(NADIR_SOURCE_DIR "/config/default.yaml"); }

// KLT alone, restarting after a second without a good frame.
Config klt_config() {
  Config config = default_config();
  config.apply_override("tracker.mode=klt");
  config.apply_override("tracker.max_gap_s=1");
  return config;
}

const SyntheticScene& scene() {
  static const SyntheticScene s(cv::Size(1400, 1400), 7);
  return s;
}

// Frame k of a steady flight over the scene.
cv::Mat frame(int k) { return scene().render({{700 + 3.0 * k, 700 - 2.0 * k}, 0.003 * k}, kFrame, 1.0, 50 + k); }

class Harness {
 public:
  explicit Harness(const Config& config = default_config()) : bus_(memq_options()) {
    node_ = make_tracker_node(config, bus_);
    bus_.subscribe_raw(channels::kTracks, [this](const std::string&, const uint8_t* data, size_t size) {
      raw.emplace_back(data, data + size);
      tracks_t msg;
      msg.decode(data, 0, static_cast<int>(size));
      tracks.push_back(msg);
    });
  }
  void send(const image_t& msg) {
    bus_.publish(channels::kCameraImage, msg);
    pump();
  }
  void send_raw(const std::vector<uint8_t>& bytes) {
    bus_.publish_raw(channels::kCameraImage, bytes.data(), bytes.size());
    pump();
  }
  StatusReport status() const { return node_->status(); }
  std::optional<double> counter(const std::string& name) const { return status().counter(name); }
  const BusErrorCounts& bus_errors() const { return bus_.error_counts(); }

  std::vector<tracks_t> tracks;
  std::vector<std::vector<uint8_t>> raw;

 private:
  static LcmBusOptions memq_options() {
    LcmBusOptions o;
    o.url = "memq://";
    return o;
  }
  void pump() {
    while (bus_.handle(0) > 0) {
    }
  }
  LcmBus bus_;
  std::unique_ptr<Node> node_;
};

TEST(TrackerNode, PublishesTracksWithBothUtimesAndNormalizedCoordinates) {
  Harness h;
  const CameraModel camera = CameraModel::from_config(default_config());
  for (int k = 0; k < 5; ++k) h.send(make_image_msg(frame(k), kStartUs + k * kPeriodUs, 100 + k));
  ASSERT_EQ(h.tracks.size(), 5u);

  const tracks_t& first = h.tracks[0];
  EXPECT_EQ(first.flags, tracks_t::FLAG_FIRST_FRAME);
  EXPECT_EQ(first.num_tracks, 0);
  EXPECT_EQ(first.prev_utime, 0);
  EXPECT_EQ(first.utime, kStartUs);

  for (int k = 1; k < 5; ++k) {
    const tracks_t& t = h.tracks[static_cast<size_t>(k)];
    EXPECT_EQ(t.flags, 0) << "frame " << k;
    EXPECT_EQ(t.utime, kStartUs + k * kPeriodUs);
    EXPECT_EQ(t.prev_utime, kStartUs + (k - 1) * kPeriodUs);
    EXPECT_EQ(t.frame_counter, 100 + k);
    EXPECT_EQ(t.width, 612);
    EXPECT_EQ(t.height, 512);
    EXPECT_GT(t.num_tracks, 380);
    ASSERT_EQ(t.track_id.size(), static_cast<size_t>(t.num_tracks));
    int from_first_frame = 0;
    for (int i = 0; i < t.num_tracks; ++i) {
      EXPECT_GE(t.age[i], 2);
      EXPECT_LE(t.age[i], k + 1) << "no feature is older than the sequence";
      from_first_frame += t.age[i] == k + 1;
    }
    EXPECT_GT(from_first_frame, 300);
    // Normalized coordinates are the camera model's undistortion of the pixels.
    std::vector<cv::Point2f> prev_px, curr_px;
    for (int i = 0; i < t.num_tracks; ++i) {
      prev_px.emplace_back(t.prev_px[i][0], t.prev_px[i][1]);
      curr_px.emplace_back(t.curr_px[i][0], t.curr_px[i][1]);
    }
    const auto prev_norm = camera.undistort(prev_px);
    const auto curr_norm = camera.undistort(curr_px);
    for (int i = 0; i < t.num_tracks; ++i) {
      EXPECT_DOUBLE_EQ(t.prev_norm[i][0], prev_norm[i].x);
      EXPECT_DOUBLE_EQ(t.prev_norm[i][1], prev_norm[i].y);
      EXPECT_DOUBLE_EQ(t.curr_norm[i][0], curr_norm[i].x);
      EXPECT_DOUBLE_EQ(t.curr_norm[i][1], curr_norm[i].y);
    }
    // A track's previous pixel is where it was in the previous message.
    const tracks_t& before = h.tracks[static_cast<size_t>(k - 1)];
    std::map<int64_t, std::pair<float, float>> earlier;
    for (int i = 0; i < before.num_tracks; ++i) earlier[before.track_id[i]] = {before.curr_px[i][0], before.curr_px[i][1]};
    int chained = 0;
    for (int i = 0; i < t.num_tracks; ++i) {
      const auto it = earlier.find(t.track_id[i]);
      if (it == earlier.end()) continue;
      ++chained;
      EXPECT_EQ(it->second.first, t.prev_px[i][0]);
      EXPECT_EQ(it->second.second, t.prev_px[i][1]);
    }
    if (k > 1) {
      EXPECT_GT(chained, 300);
    }
  }
  const StatusReport s = h.status();
  EXPECT_EQ(s.received, 5);
  EXPECT_EQ(s.published, 5);
  EXPECT_EQ(s.dropped, 0);
  EXPECT_EQ(s.errors, 0);
  EXPECT_EQ(s.state, status_t::STATE_OK) << s.detail;
  EXPECT_GT(h.counter("tracks_mean"), 380);
  EXPECT_GE(h.counter("replenished"), 450);
}

TEST(TrackerNode, BadImagesAreFlaggedCountedAndTrackedAcross) {
  Harness h;
  int64_t utime = kStartUs;
  int64_t counter = 0;
  auto next = [&](const cv::Mat& pixels) {
    image_t msg = make_image_msg(pixels, utime, counter);
    utime += kPeriodUs;
    ++counter;
    return msg;
  };
  h.send(next(frame(0)));
  h.send(next(cv::Mat(kFrame, CV_8UC1, cv::Scalar(0))));    // black
  h.send(next(cv::Mat(kFrame, CV_8UC1, cv::Scalar(255))));  // saturated
  h.send(next(cv::Mat(kFrame, CV_8UC1, cv::Scalar(90))));   // featureless
  h.send(next(cv::Mat(480, 640, CV_8UC1, cv::Scalar(90)))); // wrong size
  image_t wrong_format = next(frame(5));
  wrong_format.pixel_format = 9;
  h.send(wrong_format);
  h.send(next(frame(6)));
  // Images that do not fit their format are rejected: no TRACKS for them.
  ASSERT_EQ(h.tracks.size(), 5u);

  using T = tracks_t;
  for (int i = 1; i <= 3; ++i) {
    const T& bad = h.tracks[static_cast<size_t>(i)];
    EXPECT_TRUE(bad.flags & T::FLAG_BAD_IMAGE) << "message " << i;
    EXPECT_EQ(bad.num_tracks, 0);
    EXPECT_EQ(bad.prev_utime, kStartUs) << "the reference stays the last good frame";
  }
  EXPECT_TRUE(h.tracks[2].flags & T::FLAG_FRAME_GAP) << "a pair two frames apart is a gap";

  // The next good frame is tracked from frame 0 across the six-frame gap.
  const T& after = h.tracks[4];
  EXPECT_EQ(after.flags, T::FLAG_FRAME_GAP);
  EXPECT_EQ(after.prev_utime, kStartUs);
  EXPECT_GT(after.num_tracks, 300);

  const StatusReport s = h.status();
  EXPECT_EQ(s.received, 7);
  EXPECT_EQ(s.published, 5);
  EXPECT_EQ(s.dropped, 2);
  EXPECT_EQ(s.errors, 2) << "wrong size and wrong format are errors";
  EXPECT_EQ(h.counter("black"), 1);
  EXPECT_EQ(h.counter("saturated"), 1);
  EXPECT_EQ(h.counter("featureless"), 1);
  EXPECT_EQ(h.counter("bad_image"), 3);
  EXPECT_EQ(h.counter("wrong_format"), 2);
}

TEST(TrackerNode, StatusNamesTheLastProblem) {
  Harness h;
  h.send(make_image_msg(frame(0), kStartUs, 0));
  h.send(make_image_msg(cv::Mat(480, 640, CV_8UC1, cv::Scalar(90)), kStartUs + kPeriodUs, 1));
  const StatusReport s = h.status();
  EXPECT_EQ(s.state, status_t::STATE_WARN);
  EXPECT_NE(s.detail.find("CAMERA_IMAGE"), std::string::npos) << s.detail;
  EXPECT_NE(s.detail.find("640x480"), std::string::npos) << s.detail;
  h.send(make_image_msg(frame(2), kStartUs + 2 * kPeriodUs, 2));
  EXPECT_EQ(h.status().state, status_t::STATE_OK) << "a good frame clears the warning";
}

TEST(TrackerNode, FewFeaturesAreFlagged) {
  Harness h;
  // Texture only in a small window: fewer corners than min_tracks (20).
  cv::Mat sparse(kFrame, CV_8UC1, cv::Scalar(100));
  scene().texture()(cv::Rect(0, 0, 30, 30)).copyTo(sparse(cv::Rect(280, 230, 30, 30)));
  h.send(make_image_msg(sparse, kStartUs, 0));
  h.send(make_image_msg(sparse, kStartUs + kPeriodUs, 1));
  ASSERT_EQ(h.tracks.size(), 2u);
  EXPECT_EQ(h.tracks[0].flags, tracks_t::FLAG_FIRST_FRAME | tracks_t::FLAG_FEW_FEATURES);
  EXPECT_EQ(h.tracks[1].flags, tracks_t::FLAG_FEW_FEATURES);
  EXPECT_GT(h.tracks[1].num_tracks, 0);
  EXPECT_LT(h.tracks[1].num_tracks, 20);
  EXPECT_EQ(h.counter("few_features"), 2);
}

TEST(TrackerNode, OutOfOrderAndDuplicateImagesAreDropped) {
  Harness h;
  h.send(make_image_msg(frame(0), kStartUs, 0));
  h.send(make_image_msg(frame(2), kStartUs + 2 * kPeriodUs, 2));
  h.send(make_image_msg(frame(1), kStartUs + kPeriodUs, 1));       // late
  h.send(make_image_msg(frame(2), kStartUs + 2 * kPeriodUs, 2));   // duplicate
  h.send(make_image_msg(frame(3), kStartUs + 3 * kPeriodUs, 3));
  ASSERT_EQ(h.tracks.size(), 3u);
  EXPECT_EQ(h.tracks[1].flags, tracks_t::FLAG_FRAME_GAP);
  EXPECT_EQ(h.tracks[2].flags, 0);
  EXPECT_EQ(h.tracks[2].prev_utime, kStartUs + 2 * kPeriodUs);
  const StatusReport s = h.status();
  EXPECT_EQ(s.received, 5);
  EXPECT_EQ(s.published, 3);
  EXPECT_EQ(s.dropped, 2);
  EXPECT_EQ(h.counter("out_of_order"), 1);
  EXPECT_EQ(h.counter("rejected.CAMERA_IMAGE.time_duplicate"), 1);
}

TEST(TrackerNode, FrameGapsFromCounterOrTimeAndRestartAfterLongGaps) {
  Harness h(klt_config());
  h.send(make_image_msg(frame(0), kStartUs, 10));
  h.send(make_image_msg(frame(1), kStartUs + kPeriodUs, 12));           // counter skips
  h.send(make_image_msg(frame(2), kStartUs + 3 * kPeriodUs, 13));       // time skips
  h.send(make_image_msg(frame(3), kStartUs + 4 * kPeriodUs, -1));       // no counter, time fine
  h.send(make_image_msg(frame(4), kStartUs + 4 * kPeriodUs + 2000000, -1));  // 2 s later: restart
  // A frame that far ahead waits for the next one to confirm the stream moved.
  EXPECT_EQ(h.tracks.size(), 4u);
  h.send(make_image_msg(frame(5), kStartUs + 5 * kPeriodUs + 2000000, -1));
  ASSERT_EQ(h.tracks.size(), 6u);
  EXPECT_EQ(h.tracks[5].flags, 0);
  EXPECT_EQ(h.tracks[5].prev_utime, kStartUs + 4 * kPeriodUs + 2000000);
  EXPECT_EQ(h.tracks[1].flags, tracks_t::FLAG_FRAME_GAP);
  EXPECT_EQ(h.tracks[2].flags, tracks_t::FLAG_FRAME_GAP);
  EXPECT_EQ(h.tracks[3].flags, 0);
  EXPECT_EQ(h.tracks[4].flags, tracks_t::FLAG_FRAME_GAP | tracks_t::FLAG_FIRST_FRAME);
  EXPECT_EQ(h.tracks[4].prev_utime, 0);
  EXPECT_EQ(h.tracks[4].num_tracks, 0);
  EXPECT_EQ(h.counter("frame_gaps"), 3);
  EXPECT_EQ(h.counter("restarts"), 1);
}

TEST(TrackerNode, AFutureStampedImageLosesNoFrame) {
  Harness h;
  h.send(make_image_msg(frame(0), kStartUs, 0));
  h.send(make_image_msg(frame(1), kStartUs + kPeriodUs, 1));
  h.send(make_image_msg(frame(1), kStartUs + 10000000, 99));  // a stray stamped 10 s ahead
  for (int k = 2; k < 6; ++k) h.send(make_image_msg(frame(k), kStartUs + k * kPeriodUs, k));
  ASSERT_EQ(h.tracks.size(), 6u);
  for (size_t k = 1; k < h.tracks.size(); ++k) {
    EXPECT_EQ(h.tracks[k].utime, kStartUs + static_cast<int64_t>(k) * kPeriodUs);
    EXPECT_EQ(h.tracks[k].flags, 0) << k;
  }
  // The first status after a rejection warns and names it; the next one is OK again.
  const StatusReport s = h.status();
  EXPECT_EQ(s.state, status_t::STATE_WARN);
  EXPECT_NE(s.detail.find("CAMERA_IMAGE utime"), std::string::npos) << s.detail;
  EXPECT_EQ(s.dropped, 1);
  EXPECT_EQ(h.counter("rejected.CAMERA_IMAGE.time_ahead"), 1);
  EXPECT_EQ(h.status().state, status_t::STATE_OK);
}

TEST(TrackerNode, Mono16ImagesAreTrackedLikeMono8) {
  Harness h8, h16;
  for (int k = 0; k < 3; ++k) {
    const cv::Mat pixels = frame(k);
    image_t mono8 = make_image_msg(pixels, kStartUs + k * kPeriodUs, k);
    image_t mono16 = mono8;
    mono16.pixel_format = image_t::PIXEL_MONO16;
    mono16.stride = 2 * pixels.cols;
    mono16.data.assign(static_cast<size_t>(mono16.stride * pixels.rows), 0);
    for (size_t i = 0; i < mono8.data.size(); ++i) {
      mono16.data[2 * i] = 0x5A;              // low byte: below 8-bit resolution
      mono16.data[2 * i + 1] = mono8.data[i]; // high byte: the 8-bit value
    }
    mono16.size = static_cast<int32_t>(mono16.data.size());
    h8.send(mono8);
    h16.send(mono16);
  }
  ASSERT_EQ(h8.raw.size(), 3u);
  EXPECT_EQ(h8.raw, h16.raw);
}

TEST(TrackerNode, SameImageSequenceGivesByteIdenticalTracks) {
  std::vector<image_t> images;
  for (int k = 0; k < 8; ++k) images.push_back(make_image_msg(frame(k), kStartUs + k * kPeriodUs, k));
  images[4] = make_image_msg(cv::Mat(kFrame, CV_8UC1, cv::Scalar(0)), kStartUs + 4 * kPeriodUs, 4);
  Harness a, b;
  for (const image_t& m : images) a.send(m);
  for (const image_t& m : images) b.send(m);
  ASSERT_EQ(a.raw.size(), 8u);
  EXPECT_EQ(a.raw, b.raw);
}

TEST(TrackerNode, SurvivesMalformedMessages) {
  Harness h;
  h.send_raw({1, 2, 3, 4, 5});
  image_t truncated_source = make_image_msg(frame(0), kStartUs, 0);
  std::vector<uint8_t> bytes(static_cast<size_t>(truncated_source.getEncodedSize()));
  truncated_source.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  bytes.resize(bytes.size() / 2);
  h.send_raw(bytes);
  EXPECT_EQ(h.bus_errors().malformed, 2);
  h.send(make_image_msg(frame(0), kStartUs, 0));
  h.send(make_image_msg(frame(1), kStartUs + kPeriodUs, 1));
  ASSERT_EQ(h.tracks.size(), 2u);
  EXPECT_GT(h.tracks[1].num_tracks, 300);
}

// A photo survey as nadir_import writes it: frames tens of seconds apart,
// turning 180 degrees between two of them, tracker.mode descriptor and a
// max_gap_s beyond the longest gap.
Config survey_config(const std::string& mode) {
  Config config = default_config();
  config.apply_override("tracker.mode=" + mode);
  config.apply_override("tracker.max_gap_s=120");
  config.apply_override("input_checks.max_ahead_s=120");
  return config;
}

cv::Mat survey_photo(int k) {
  // 40 % of a frame width between photos, the heading reversed at photo 2.
  const double x = 500 + 0.4 * kFrame.width * k;
  return scene().render({{x, 700}, k >= 2 ? CV_PI : 0.0}, kFrame, 1.0, 70 + k);
}

TEST(TrackerNode, DescriptorModeTracksPhotosTensOfSecondsApart) {
  Harness h(survey_config("descriptor"));
  const CameraModel camera = CameraModel::from_config(default_config());
  const int64_t gap_us = 45000000;  // 45 s
  for (int k = 0; k < 4; ++k) h.send(make_image_msg(survey_photo(k), kStartUs + k * gap_us, k));
  ASSERT_EQ(h.tracks.size(), 4u);
  EXPECT_EQ(h.tracks[0].flags, tracks_t::FLAG_FIRST_FRAME);
  EXPECT_GT(h.counter("descriptor_frames"), 2.5);
  EXPECT_EQ(h.counter("restarts"), 0);
  for (size_t k = 1; k < 4; ++k) {
    const tracks_t& t = h.tracks[k];
    EXPECT_EQ(t.flags, tracks_t::FLAG_FRAME_GAP) << "photo " << k;
    EXPECT_EQ(t.prev_utime, kStartUs + static_cast<int64_t>(k - 1) * gap_us);
    EXPECT_GT(t.num_tracks, 100) << "photo " << k;
    // Pixels follow the known motion; normalized = the camera's undistortion.
    const ViewPose from{{500 + 0.4 * kFrame.width * static_cast<double>(k - 1), 700}, k - 1 >= 2 ? CV_PI : 0.0};
    const ViewPose to{{500 + 0.4 * kFrame.width * static_cast<double>(k), 700}, k >= 2 ? CV_PI : 0.0};
    std::vector<cv::Point2f> curr_px;
    for (int i = 0; i < t.num_tracks; ++i) {
      const cv::Point2d expected = SyntheticScene::map_point({t.prev_px[i][0], t.prev_px[i][1]}, from, to, kFrame);
      EXPECT_LT(std::hypot(expected.x - t.curr_px[i][0], expected.y - t.curr_px[i][1]), 9.0);
      curr_px.emplace_back(t.curr_px[i][0], t.curr_px[i][1]);
      if (i > 0) {
        EXPECT_GT(t.track_id[i], t.track_id[i - 1]);
      }
    }
    const auto curr_norm = camera.undistort(curr_px);
    for (int i = 0; i < t.num_tracks; ++i) EXPECT_DOUBLE_EQ(t.curr_norm[i][0], curr_norm[i].x);
  }
  // Keypoints matched again keep their id; their age counts the photos.
  int chained = 0;
  for (int i = 0; i < h.tracks[2].num_tracks; ++i) chained += h.tracks[2].age[i] == 3;
  EXPECT_GT(chained, 20);

  // The same photos again: the same bytes.
  Harness again(survey_config("descriptor"));
  for (int k = 0; k < 4; ++k) again.send(make_image_msg(survey_photo(k), kStartUs + k * gap_us, k));
  EXPECT_EQ(h.raw, again.raw);
}

TEST(TrackerNode, AutoModeUsesDescriptorsForLongStepsOrWhenKltLosesTrack) {
  Config config = survey_config("auto");
  config.apply_override("tracker.auto_min_tracks=40");  // the default is 0: long steps only
  Harness h(config);
  // Steady 14 Hz frames: KLT.
  for (int k = 0; k < 3; ++k) h.send(make_image_msg(frame(k), kStartUs + k * kPeriodUs, k));
  EXPECT_EQ(h.counter("descriptor_frames"), 0);
  EXPECT_GT(h.tracks[2].num_tracks, 380);
  // 5 s later (beyond auto_max_interval_s): descriptors.
  const int64_t later = kStartUs + 2 * kPeriodUs + 5000000;
  h.send(make_image_msg(frame(40), later, 3));
  EXPECT_EQ(h.counter("descriptor_frames"), 1);
  EXPECT_GT(h.tracks[3].num_tracks, 100);
  // Back to 14 Hz: KLT again, from the frame the descriptors matched into,
  // with ids above every id used so far.
  int64_t max_id = 0;
  for (const tracks_t& t : h.tracks)
    for (int64_t id : t.track_id) max_id = std::max(max_id, id);
  h.send(make_image_msg(frame(41), later + kPeriodUs, 4));
  EXPECT_EQ(h.counter("descriptor_frames"), 1);
  EXPECT_GT(h.tracks[4].num_tracks, 380);
  for (int64_t id : h.tracks[4].track_id) EXPECT_GT(id, max_id);
  // One period later but turned half round: KLT keeps too few tracks, the
  // same pair is matched with descriptors.
  const cv::Mat turned = scene().render({{700 + 3.0 * 42, 700 - 2.0 * 42}, CV_PI}, kFrame, 1.0, 99);
  h.send(make_image_msg(turned, later + 2 * kPeriodUs, 5));
  EXPECT_EQ(h.counter("descriptor_frames"), 2);
  EXPECT_GT(h.tracks[5].num_tracks, 100);
  EXPECT_EQ(h.tracks[5].prev_utime, later + kPeriodUs);
}

// The default configuration over 10 s of featureless ground (flagged, the
// last good frame kept): the first good frame after it is matched with the
// last good one (a third of the image still overlaps), not restarted from,
// and the features land where the known motion puts them; KLT goes on from it.
TEST(TrackerNode, DefaultMatchesTheLastGoodFrameAcrossTenSecondsOfFeaturelessGround) {
  Harness h;
  for (int k = 0; k < 3; ++k) h.send(make_image_msg(frame(k), kStartUs + k * kPeriodUs, k));
  const int last_good = 2, back = 143;
  for (int k = last_good + 1; k < back; ++k) {
    h.send(make_image_msg(cv::Mat(kFrame, CV_8UC1, cv::Scalar(90)), kStartUs + k * kPeriodUs, k));
  }
  h.send(make_image_msg(frame(back), kStartUs + back * kPeriodUs, back));
  h.send(make_image_msg(frame(back + 1), kStartUs + (back + 1) * kPeriodUs, back + 1));
  ASSERT_EQ(h.tracks.size(), static_cast<size_t>(back + 2));
  EXPECT_EQ(h.counter("restarts"), 0);
  EXPECT_EQ(h.counter("featureless"), back - last_good - 1);
  const tracks_t& across = h.tracks[back];
  EXPECT_EQ(across.prev_utime, kStartUs + last_good * kPeriodUs);
  EXPECT_EQ(across.flags, tracks_t::FLAG_FRAME_GAP);
  EXPECT_GT(across.num_tracks, 50);
  const ViewPose from{{700 + 3.0 * last_good, 700 - 2.0 * last_good}, 0.003 * last_good};
  const ViewPose to{{700 + 3.0 * back, 700 - 2.0 * back}, 0.003 * back};
  for (int i = 0; i < across.num_tracks; ++i) {
    const cv::Point2d expected =
        SyntheticScene::map_point({across.prev_px[i][0], across.prev_px[i][1]}, from, to, kFrame);
    EXPECT_LT(std::hypot(expected.x - across.curr_px[i][0], expected.y - across.curr_px[i][1]), 9.0) << i;
  }
  EXPECT_EQ(h.tracks[back + 1].prev_utime, kStartUs + back * kPeriodUs);
  EXPECT_EQ(h.tracks[back + 1].flags, 0);
  EXPECT_GT(h.tracks[back + 1].num_tracks, 380);
}

TEST(TrackerNode, KltModeHasNoDescriptorCounters) {
  Harness h(klt_config());
  h.send(make_image_msg(frame(0), kStartUs, 0));
  for (const auto& [key, value] : h.status().counters) EXPECT_EQ(key.find("descriptor"), std::string::npos) << key;
}

TEST(TrackerNode, BadConfigFailsAtStartNamingTheKey) {
  Config config = Config::parse(
      "camera: {width: 612, height: 512, fx: 400, fy: 400, cx: 306, cy: 256}\n"
      "tracker: {klt_pyramid_levels: 0}\n",
      "bad.yaml");
  LcmBusOptions o;
  o.url = "memq://";
  LcmBus bus(o);
  try {
    make_tracker_node(config, bus);
    FAIL() << "expected a ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("tracker.klt_pyramid_levels"), std::string::npos) << e.what();
  }
}

TEST(TrackerNode, RegistersUnderItsName) {
  NodeRegistry registry;
  register_tracker_node(registry);
  ASSERT_NE(registry.find("tracker"), nullptr);
  LcmBusOptions o;
  o.url = "memq://";
  LcmBus bus(o);
  const auto node = (*registry.find("tracker"))(default_config(), bus);
  EXPECT_EQ(node->name(), "tracker");
  EXPECT_EQ(node->output_channels(), std::vector<std::string>{channels::kTracks});
}

TEST(TrackerProcess, HelpDescribesTheProcess) {
  const char* bin_dir = std::getenv("NADIR_BIN_DIR");
  ASSERT_NE(bin_dir, nullptr);
  const std::string command = std::string(bin_dir) + "/nadir_tracker --help";
  FILE* pipe = popen(command.c_str(), "r");
  ASSERT_NE(pipe, nullptr);
  std::string text;
  char chunk[512];
  while (fgets(chunk, sizeof chunk, pipe) != nullptr) text += chunk;
  EXPECT_EQ(pclose(pipe), 0);
  EXPECT_NE(text.find("KLT"), std::string::npos) << text;
  EXPECT_NE(text.find("--config"), std::string::npos) << text;
}

}  // namespace
}  // namespace nadir
