#pragma once
// The tracker process: CAMERA_IMAGE in, one TRACKS out per image received in
// order. Bad images (wrong format or size, black, saturated, featureless) give
// a flagged TRACKS with no tracks and keep the last good frame as reference,
// so the next good frame is tracked across the gap (FLAG_FRAME_GAP). Images
// older than the last one are dropped and counted. Pixels are distorted; the
// normalized coordinates come from the camera model of the same config.
//
// TRACKS fields: prev_utime is the sensor time of the frame prev_px were
// measured in, 0 when there is none (FLAG_FIRST_FRAME); age is the number of
// frames a feature has been seen in (2 the first time it is published).

#include <cstdint>
#include <exception>
#include <memory>
#include <string>

#include "common/bus.h"
#include "common/camera_model.h"
#include "common/config.h"
#include "common/input_checks.h"
#include "common/node.h"
#include "nadir/image_t.hpp"
#include "nadir/tracks_t.hpp"
#include "processes/tracker/descriptor_matcher.h"
#include "processes/tracker/feature_tracker.h"
#include "processes/tracker/track_end_norms.h"
#include "processes/tracker/tracker_options.h"

namespace nadir {

class TrackerNode : public Node {
 public:
  // Throws ConfigError for a bad `camera:` or `tracker:` section.
  TrackerNode(const Config& root, Bus& bus);

  std::string name() const override { return "tracker"; }
  std::vector<std::string> output_channels() const override;
  StatusReport status() const override;

  // The subscription handler; public so a benchmark can drive it directly.
  void on_image(const image_t& msg);
  void track_image(const image_t& msg);

 private:
  tracks_t make_header(const image_t& msg) const;
  void publish(tracks_t& out, const std::string& problem);
  // Counts the error and starts afresh; returns the problem for STATUS.
  std::string tracking_failed(const std::exception& e, int64_t utime);
  int32_t gap_flags(const image_t& msg, bool* too_long) const;
  // Pairs the reference frame with `gray` by tracker.mode; sets *by_descriptor.
  TrackStepResult pair_frames(const cv::Mat& gray, int64_t utime, bool* by_descriptor);
  // `auto`: the descriptor matcher on the last good frame (ref_gray_) and
  // `gray`; KLT then starts afresh from `gray`. Ids stay unique across both.
  TrackStepResult match_instead_of_klt(const cv::Mat& gray, int64_t utime);

  Bus& bus_;
  TrackerOptions options_;
  CameraModel camera_;
  InputGate gate_;
  int64_t max_ahead_us_;
  std::unique_ptr<image_t> held_;  // a frame far ahead of the stream, until the next one confirms it
  FeatureTracker tracker_;
  std::unique_ptr<DescriptorMatcher> matcher_;  // modes descriptor and auto
  cv::Mat ref_gray_;                            // auto: the last good frame, for the matcher
  int64_t matcher_ref_utime_ = -1;              // auto: the frame the matcher holds as reference
  TrackEndNorms track_end_norms_;  // last frame's curr_norm: this frame's prev_norm
  cv::Mat convert_buffer_;

  bool have_last_ = false;     // any image accepted in order
  int64_t last_utime_ = 0;
  bool have_reference_ = false;  // last good frame, what the tracker holds
  int64_t ref_utime_ = 0;
  int64_t ref_frame_counter_ = 0;

  // Status counters.
  int64_t received_ = 0, published_ = 0, dropped_ = 0, errors_ = 0;
  int64_t out_of_order_ = 0, wrong_format_ = 0, bad_image_ = 0, black_ = 0, saturated_ = 0, featureless_ = 0;
  int64_t few_features_ = 0, frame_gaps_ = 0, restarts_ = 0, tracked_frames_ = 0;
  int64_t tracks_total_ = 0, replenished_ = 0, fb_rejected_ = 0, patch_rejected_ = 0, klt_lost_ = 0, out_of_image_ = 0;
  int64_t last_tracks_ = 0;
  int64_t descriptor_frames_ = 0, descriptor_candidates_ = 0, descriptor_inliers_ = 0, geometry_failed_ = 0;
  std::string last_problem_;
  int32_t last_flags_ = 0;
};

std::unique_ptr<Node> make_tracker_node(const Config& root, Bus& bus);
void register_tracker_node(NodeRegistry& registry);

}  // namespace nadir
