#include "processes/tracker/tracker_node.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <sstream>

#include "common/channels.h"
#include "nadir/status_t.hpp"
#include "processes/tracker/image_input.h"

namespace nadir {

namespace {
// One frame confirms a frame far ahead of the stream (it is held until then).
InputCheckOptions image_checks(const Config& root) {
  InputCheckOptions checks = InputCheckOptions::from_config(root);
  checks.relock_messages = 2;
  return checks;
}
}  // namespace

TrackerNode::TrackerNode(const Config& root, Bus& bus)
    : bus_(bus),
      options_(TrackerOptions::from_config(root)),
      camera_(CameraModel::from_config(root)),
      gate_(image_checks(root)),
      max_ahead_us_(static_cast<int64_t>(gate_.options().max_ahead_s * 1e6)),
      tracker_(options_, &camera_) {
  if (options_.mode != TrackerMode::kKlt) matcher_ = std::make_unique<DescriptorMatcher>(options_.descriptor, camera_);
  bus_.subscribe<image_t>(channels::kCameraImage, [this](const image_t& msg) { on_image(msg); });
}

std::vector<std::string> TrackerNode::output_channels() const { return {channels::kTracks}; }

tracks_t TrackerNode::make_header(const image_t& msg) const {
  tracks_t out{};
  out.utime = msg.utime;
  out.prev_utime = have_reference_ ? ref_utime_ : 0;
  out.frame_counter = msg.frame_counter;
  out.width = msg.width;
  out.height = msg.height;
  out.flags = 0;
  out.num_tracks = 0;
  return out;
}

int32_t TrackerNode::gap_flags(const image_t& msg, bool* too_long) const {
  *too_long = false;
  if (!have_reference_) return 0;
  const double period_us = 1e6 / camera_.rate_hz;
  const int64_t step_us = msg.utime - ref_utime_;
  *too_long = static_cast<double>(step_us) > options_.max_gap_s * 1e6;
  const bool counter_gap = msg.frame_counter >= 0 && ref_frame_counter_ >= 0 && msg.frame_counter != ref_frame_counter_ + 1;
  const bool time_gap = static_cast<double>(step_us) > options_.gap_factor * period_us;
  return (counter_gap || time_gap) ? tracks_t::FLAG_FRAME_GAP : 0;
}

void TrackerNode::publish(tracks_t& out, const std::string& problem) {
  if (out.flags & tracks_t::FLAG_FEW_FEATURES) ++few_features_;
  if (out.flags & tracks_t::FLAG_FRAME_GAP) ++frame_gaps_;
  last_flags_ = out.flags;
  last_problem_ = problem;
  if (problem.empty() && (out.flags & tracks_t::FLAG_FEW_FEATURES)) {
    last_problem_ = "few features: " + std::to_string(out.num_tracks) + " tracks < " + std::to_string(options_.min_tracks);
  }
  bus_.publish(channels::kTracks, out);
  ++published_;
}

void TrackerNode::on_image(const image_t& msg) {
  ++received_;
  // An image whose size, stride or data length do not fit its format (or the
  // camera's) is rejected like any impossible input: no TRACKS for it, so a
  // stray message between two frames cannot split their pair.
  const ImageFormatCheck format = check_image_format(msg, camera_.width, camera_.height);
  if (!format.ok) {
    ++wrong_format_;
    ++errors_;
    ++dropped_;
    last_problem_ = "CAMERA_IMAGE utime " + std::to_string(msg.utime) + ": " + format.reason + ", rejected";
    return;
  }
  if (!gate_.admit(channels::kCameraImage, msg)) {
    // A frame far ahead of the stream waits for the next one: if that agrees
    // with it, the camera really moved on (a gap) and both are tracked; if the
    // next one continues the old stream, the held frame was a stray.
    const bool ahead = have_last_ && msg.utime > last_utime_;
    if (held_ || !ahead) ++dropped_;
    if (ahead) held_ = std::make_unique<image_t>(msg);
    return;
  }
  if (held_) {
    std::unique_ptr<image_t> held = std::move(held_);
    if (have_last_ && msg.utime > held->utime && msg.utime - last_utime_ > max_ahead_us_) {
      track_image(*held);
    } else {
      ++dropped_;
    }
  }
  track_image(msg);
}

void TrackerNode::track_image(const image_t& msg) {
  if (have_last_ && msg.utime <= last_utime_) {
    ++dropped_;
    ++out_of_order_;
    return;
  }
  have_last_ = true;
  last_utime_ = msg.utime;

  tracks_t out = make_header(msg);
  bool too_long = false;
  out.flags |= gap_flags(msg, &too_long);

  const cv::Mat gray = to_gray8(msg, options_.mono16_significant_bits, convert_buffer_);
  const ImageQualityCheck quality = check_image_quality(gray, options_);
  if (quality.quality != ImageQuality::kGood) {
    ++bad_image_;
    if (quality.quality == ImageQuality::kBlack) ++black_;
    if (quality.quality == ImageQuality::kSaturated) ++saturated_;
    if (quality.quality == ImageQuality::kFeatureless) ++featureless_;
    out.flags |= tracks_t::FLAG_BAD_IMAGE;
    publish(out, "CAMERA_IMAGE utime " + std::to_string(msg.utime) + ": " + quality.reason);
    return;
  }

  if (too_long) {
    // The reference is too old to track from: start again from this frame.
    tracker_.reset();
    if (matcher_) matcher_->reset();
    have_reference_ = false;
    out.prev_utime = 0;
    ++restarts_;
  }
  TrackStepResult step;
  bool by_descriptor = false;
  try {
    step = pair_frames(gray, msg.utime, &by_descriptor);
  } catch (const std::exception& e) {
    // Not expected after the checks above; still one flagged TRACKS per
    // image, a counted error and a fresh start rather than a lost message.
    out.flags |= tracks_t::FLAG_BAD_IMAGE;
    publish(out, tracking_failed(e, msg.utime));
    return;
  }
  if (step.first_frame) out.flags |= tracks_t::FLAG_FIRST_FRAME;
  // A first frame has no tracks by nature; it is short of features when
  // detection found too few to track from.
  const int usable = step.first_frame ? step.features_after : static_cast<int>(step.tracks.size());
  if (usable < options_.min_tracks) out.flags |= tracks_t::FLAG_FEW_FEATURES;

  const size_t n = step.tracks.size();
  out.num_tracks = static_cast<int32_t>(n);
  out.track_id.resize(n);
  out.age.resize(n);
  // LCM's C++ type holds [n][2] arrays as vectors of 2-element vectors.
  out.prev_px.assign(n, std::vector<float>(2));
  out.curr_px.assign(n, std::vector<float>(2));
  out.prev_norm.assign(n, std::vector<double>(2));
  out.curr_norm.assign(n, std::vector<double>(2));
  std::vector<cv::Point2f> prev_px(n), curr_px(n);
  for (size_t i = 0; i < n; ++i) {
    const FeatureTrack& t = step.tracks[i];
    out.track_id[i] = t.id;
    out.age[i] = t.age;
    out.prev_px[i][0] = t.prev_px.x;
    out.prev_px[i][1] = t.prev_px.y;
    out.curr_px[i][0] = t.curr_px.x;
    out.curr_px[i][1] = t.curr_px.y;
    prev_px[i] = t.prev_px;
    curr_px[i] = t.curr_px;
  }
  const std::vector<cv::Point2d> prev_norm = track_end_norms_.undistort_prev(out.track_id, prev_px, camera_);
  const std::vector<cv::Point2d> curr_norm = camera_.undistort(curr_px);
  track_end_norms_.remember(out.track_id, curr_px, curr_norm);
  for (size_t i = 0; i < n; ++i) {
    out.prev_norm[i][0] = prev_norm[i].x;
    out.prev_norm[i][1] = prev_norm[i].y;
    out.curr_norm[i][0] = curr_norm[i].x;
    out.curr_norm[i][1] = curr_norm[i].y;
  }

  if (!step.first_frame) {
    ++tracked_frames_;
    tracks_total_ += static_cast<int64_t>(n);
  }
  if (by_descriptor && !step.first_frame) {
    const DescriptorStepStats& d = matcher_->last_stats();
    ++descriptor_frames_;
    descriptor_candidates_ += d.candidates;
    descriptor_inliers_ += d.inliers;
    if (d.geometry_failed) ++geometry_failed_;
  }
  if (step.first_frame || by_descriptor) replenished_ += step.replenished;
  fb_rejected_ += step.fb_rejected;
  patch_rejected_ += step.patch_rejected;
  klt_lost_ += step.klt_lost;
  out_of_image_ += step.out_of_image;
  last_tracks_ = static_cast<int64_t>(n);
  have_reference_ = true;
  ref_utime_ = msg.utime;
  ref_frame_counter_ = msg.frame_counter;
  if (options_.mode == TrackerMode::kAuto) gray.copyTo(ref_gray_);
  publish(out, "");
  // In one process with the solver and yaw fusion (nadir_composed, lockstep
  // replay) they take the TRACKS now, not after the replenishment below.
  bus_.deliver_pending();
  if (step.first_frame || by_descriptor || options_.mode == TrackerMode::kDescriptor) return;
  try {
    tracker_.prepare_next(gray, step);
    replenished_ += step.replenished;
  } catch (const std::exception& e) {
    // This frame's TRACKS is out; the next frame starts afresh.
    last_problem_ = tracking_failed(e, msg.utime);
  }
}

TrackStepResult TrackerNode::pair_frames(const cv::Mat& gray, int64_t utime, bool* by_descriptor) {
  *by_descriptor = false;
  if (options_.mode == TrackerMode::kDescriptor) {
    *by_descriptor = true;
    return matcher_->process(gray);
  }
  const bool automatic = options_.mode == TrackerMode::kAuto && have_reference_;
  const bool long_step = automatic && static_cast<double>(utime - ref_utime_) > options_.auto_max_interval_s * 1e6;
  TrackStepResult step;
  if (!long_step) {
    step = tracker_.track_frame(gray);
    // A first frame's TRACKS reports how many corners it found; otherwise
    // the new corners are only for the next frame and wait until this
    // frame's tracks are out.
    if (step.first_frame) tracker_.prepare_next(gray, step);
  }
  if (automatic && (long_step || static_cast<int>(step.tracks.size()) < options_.auto_min_tracks)) {
    *by_descriptor = true;
    return match_instead_of_klt(gray, utime);
  }
  return step;
}

TrackStepResult TrackerNode::match_instead_of_klt(const cv::Mat& gray, int64_t utime) {
  matcher_->set_next_id(std::max(matcher_->next_id(), tracker_.next_id()));
  if (!matcher_->has_reference() || matcher_ref_utime_ != ref_utime_) matcher_->set_reference(ref_gray_);
  TrackStepResult step = matcher_->process(gray);
  matcher_ref_utime_ = utime;
  // KLT cannot continue from the old reference: it starts from this frame.
  tracker_.reset();
  tracker_.set_next_id(matcher_->next_id());
  TrackStepResult restart = tracker_.track_frame(gray);
  tracker_.prepare_next(gray, restart);
  return step;
}

std::string TrackerNode::tracking_failed(const std::exception& e, int64_t utime) {
  ++errors_;
  tracker_.reset();
  if (matcher_) matcher_->reset();
  have_reference_ = false;
  return "CAMERA_IMAGE utime " + std::to_string(utime) + ": tracking failed: " + e.what();
}

StatusReport TrackerNode::status() const {
  StatusReport r;
  r.received = received_;
  r.published = published_;
  r.dropped = dropped_;
  r.errors = errors_;
  if (!last_problem_.empty()) {
    r.state = status_t::STATE_WARN;
    r.detail = last_problem_;
  }
  const double tracks_mean = tracked_frames_ > 0 ? static_cast<double>(tracks_total_) / tracked_frames_ : 0.0;
  r.counters = {
      {"tracks_last", static_cast<double>(last_tracks_)},
      {"tracks_mean", tracks_mean},
      {"tracked_frames", static_cast<double>(tracked_frames_)},
      {"replenished", static_cast<double>(replenished_)},
      {"fb_rejected", static_cast<double>(fb_rejected_)},
      {"patch_rejected", static_cast<double>(patch_rejected_)},
      {"klt_lost", static_cast<double>(klt_lost_)},
      {"out_of_image", static_cast<double>(out_of_image_)},
      {"out_of_order", static_cast<double>(out_of_order_)},
      {"frame_gaps", static_cast<double>(frame_gaps_)},
      {"restarts", static_cast<double>(restarts_)},
      {"wrong_format", static_cast<double>(wrong_format_)},
      {"bad_image", static_cast<double>(bad_image_)},
      {"black", static_cast<double>(black_)},
      {"saturated", static_cast<double>(saturated_)},
      {"featureless", static_cast<double>(featureless_)},
      {"few_features", static_cast<double>(few_features_)},
      {"last_flags", static_cast<double>(last_flags_)},
  };
  if (matcher_) {  // modes descriptor and auto only: klt's STATUS stays as it was
    r.counters.push_back({"descriptor_frames", static_cast<double>(descriptor_frames_)});
    r.counters.push_back({"descriptor_candidates", static_cast<double>(descriptor_candidates_)});
    r.counters.push_back({"descriptor_inliers", static_cast<double>(descriptor_inliers_)});
    r.counters.push_back({"geometry_failed", static_cast<double>(geometry_failed_)});
  }
  gate_.add_counters(&r);
  gate_.warn_if_rejecting(&r);
  return r;
}

std::unique_ptr<Node> make_tracker_node(const Config& root, Bus& bus) {
  return std::make_unique<TrackerNode>(root, bus);
}

void register_tracker_node(NodeRegistry& registry) { registry.add("tracker", make_tracker_node); }

}  // namespace nadir
