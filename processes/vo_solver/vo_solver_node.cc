#include "processes/vo_solver/vo_solver_node.h"

#include <cmath>
#include <string>

#include "common/channels.h"
#include "common/geometry.h"
#include "common/vo_quality.h"
#include "processes/vo_solver/delta_uncertainty.h"
#include "processes/vo_solver/heading_check.h"
#include "processes/vo_solver/lever_arm.h"

namespace nadir {

VoSolverNode::VoSolverNode(const VoSolverOptions& options, Bus& bus, const InputCheckOptions& checks)
    : options_(options),
      bus_(bus),
      sync_(options.sync, options.default_beam_body),
      depth_map_(options.solver),
      gate_(checks) {
  bus_.subscribe<tracks_t>(channels::kTracks, [this](const tracks_t& m) { on_tracks(m); });
  bus_.subscribe<ins_t>(channels::kIns, [this](const ins_t& m) { on_ins(m); });
  bus_.subscribe<altimeter_t>(channels::kAltimeter, [this](const altimeter_t& m) { on_altimeter(m); });
}

std::vector<std::string> VoSolverNode::output_channels() const {
  if (options_.solver.variant == vo::Variant::kFeatureDepth) return {channels::kVoDelta, channels::kVoGround};
  return {channels::kVoDelta};
}

void VoSolverNode::on_ins(const ins_t& ins) {
  ++received_;
  if (!gate_.admit(channels::kIns, ins)) return;
  sync_.add_ins(ins);
  process_ready();
}

void VoSolverNode::on_altimeter(const altimeter_t& altimeter) {
  ++received_;
  if (!gate_.admit(channels::kAltimeter, altimeter)) return;
  sync_.add_altimeter(altimeter);
  process_ready();
}

void VoSolverNode::on_tracks(const tracks_t& tracks) {
  ++received_;
  if (!gate_.admit(channels::kTracks, tracks)) return;
  if (pending_.count(tracks.utime)) {
    ++duplicate_tracks_;  // the same frame twice: keep the first
    return;
  }
  if (tracks.utime <= last_published_utime_) ++late_tracks_;
  pending_.emplace(tracks.utime, tracks);
  // Bounded queue: without INS the oldest frame is flushed as a flagged message.
  while (static_cast<int>(pending_.size()) > options_.sync.max_pending_frames) {
    auto oldest = pending_.begin();
    ++dropped_;
    publish(solve_frame(oldest->second, true));
    pending_.erase(oldest);
  }
  process_ready();
}

void VoSolverNode::process_ready() {
  // In utime order; readiness only grows with utime, so stop at the first wait.
  while (!pending_.empty()) {
    auto first = pending_.begin();
    if (!sync_.ready(first->first)) break;
    publish(solve_frame(first->second, false));
    pending_.erase(first);
  }
}

vo_delta_t VoSolverNode::solve_frame(const tracks_t& tracks, bool flush) {
  vo_delta_t out{};
  out.utime = tracks.utime;
  out.prev_utime = tracks.prev_utime;
  out.variant = vo::variant_name(options_.solver.variant);
  ground_ = ground_points_t{};
  int quality = 0;
  const bool first_frame = (tracks.flags & tracks_t::FLAG_FIRST_FRAME) || tracks.prev_utime >= tracks.utime;
  const bool time_gap = !first_frame && tracks.utime - tracks.prev_utime > options_.sync.max_frame_interval_us;
  if ((tracks.flags & tracks_t::FLAG_FRAME_GAP) || time_gap) quality |= vo::kFrameGap;
  // Own depths never cross a time gap, a tracker reset or a frame without an
  // estimate. A dropped frame within max_frame_interval keeps them: they are
  // for this pair's prev frame, the last one solved (FeatureDepthMap::fill
  // checks), and the tracks continue over the longer baseline.
  if (time_gap || flush || first_frame) {
    depth_map_.reset();
    velocity_.reset();
    curr_range_ = {};
  }
  if (flush) {
    // Never got its INS: keep the frame's time but say why there is no estimate.
    out.quality = quality | vo::kNoAttitude;
    return out;
  }
  const vo::FrameState curr = sync_.frame_state(tracks.utime);  // cached for the next pair too
  if (first_frame || tracks.num_tracks <= 0) {
    out.quality = quality | vo::kTooFewFeatures;
    out.outliers = std::max(0, tracks.num_tracks);
    return out;
  }
  const vo::FrameState prev = sync_.frame_state(tracks.prev_utime);
  if (!prev.has_attitude || !curr.has_attitude) quality |= vo::kNoAttitude;
  if (!curr.has_range) quality |= vo::kNoAltimeter;
  if (curr.range_stale) quality |= vo::kStaleAltimeter;
  if (options_.solver.variant == vo::Variant::kFlow) {
    if (!prev.has_range) quality |= vo::kNoAltimeter;
    if (prev.range_stale) quality |= vo::kStaleAltimeter;
  }
  if (quality & (vo::kNoAttitude | vo::kNoAltimeter)) {
    depth_map_.reset();
    out.quality = quality;
    out.outliers = tracks.num_tracks;
    return out;
  }

  vo::FramePair pair;
  pair.body_from_camera = options_.body_from_camera;
  pair.prev_roll = prev.roll;
  pair.prev_pitch = prev.pitch;
  pair.prev_yaw = prev.yaw;
  pair.curr_roll = curr.roll;
  pair.curr_pitch = curr.pitch;
  pair.curr_yaw = curr.yaw;
  pair.prev_attitude_noise_share = prev.attitude_noise_share;
  pair.curr_attitude_noise_share = curr.attitude_noise_share;
  pair.prev_range_m = prev.range_m;
  pair.curr_range_m = curr.range_m;
  pair.prev_range_sigma_m = options_.uncertainty.range_stddev(prev.range_m);
  pair.prev_beam_body = prev.beam_body;
  pair.curr_beam_body = curr.beam_body;
  const int n = std::min<int>(tracks.num_tracks,
                              static_cast<int>(std::min(tracks.prev_norm.size(), tracks.curr_norm.size())));
  pair.prev_norm.reserve(n);
  pair.curr_norm.reserve(n);
  const bool own_depths = options_.solver.variant == vo::Variant::kFeatureDepth;
  std::vector<int64_t> ids;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector2d p(tracks.prev_norm[i][0], tracks.prev_norm[i][1]);
    const Eigen::Vector2d c(tracks.curr_norm[i][0], tracks.curr_norm[i][1]);
    if (!p.allFinite() || !c.allFinite()) {
      ++bad_features_;
      continue;
    }
    pair.prev_norm.push_back(p);
    pair.curr_norm.push_back(c);
    if (own_depths) ids.push_back(i < static_cast<int>(tracks.track_id.size()) ? tracks.track_id[i] : -1 - i);
  }
  if (own_depths) depth_map_.fill(ids, tracks.prev_utime, &pair);
  const bool move_ranges = own_depths && options_.solver.feature_depth.range_from_sample_position;
  if (move_ranges) {
    // A range older than its frame, moved to the camera at the frame with the
    // velocity up to prev (this pair's own is not solved yet). Worked out once
    // per frame, when it is curr, and kept for the pair where it is prev (one
    // range per frame, as one attitude, so that they telescope); a prev frame
    // solved without a velocity keeps its range as sampled.
    if (curr_range_.utime == tracks.prev_utime) {
      pair.prev_range_m = curr_range_.range_m;
      pair.prev_beam_body = curr_range_.beam_body;
    }
    Eigen::Vector3d velocity;
    if (velocity_.at(tracks.prev_utime, &velocity)) {
      vo::move_range_to_frame(1e-6 * static_cast<double>(curr.range_age_us), velocity,
                              {curr.range_roll, curr.range_pitch}, {curr.roll, curr.pitch}, &pair.curr_range_m,
                              &pair.curr_beam_body);
    }
    curr_range_ = {tracks.utime, pair.curr_range_m, pair.curr_beam_body};
  }
  vo::Estimate est = vo::solve(pair, options_.solver);
  if (own_depths) {
    depth_map_.update(ids, tracks.utime, pair, est);
    fill_ground_points(pair, tracks.utime);
    if (!est.own_depths_used) ++paper_alone_pairs_;
    if (est.scale_carried) ++carried_scale_pairs_;
  }
  if (move_ranges) {
    if (est.quality & vo::kEstimateFailed) {
      velocity_.reset();
    } else {
      velocity_.add(tracks.prev_utime, tracks.utime, est.translation, est.dyaw);
    }
  }
  if (!(est.quality & vo::kEstimateFailed) &&
      vo::heading_contradicts_ins(est.dyaw, pair.prev_yaw, pair.curr_yaw, options_.heading)) {
    est.quality |= vo::kHeadingContradicts;
  }
  vo::add_sensor_uncertainty(pair, options_.solver, options_.uncertainty, &est);  // INS and altimeter errors
  vo::move_to_ins_reference(pair, options_.sync.calibration.camera_lever_arm_m, &est);
  out.dx = est.translation.x();
  out.dy = est.translation.y();
  out.dz = est.translation.z();
  out.dyaw = est.dyaw;
  out.ground_roll = est.ground_roll;
  out.ground_pitch = est.ground_pitch;
  for (int r = 0; r < 6; ++r)
    for (int c = 0; c < 6; ++c) out.covariance[r][c] = est.covariance(r, c);
  out.altitude_m = est.altitude_m;
  out.inliers = est.inliers;
  out.outliers = est.outliers + (tracks.num_tracks - static_cast<int>(pair.prev_norm.size()));
  out.residual_rms_px = est.residual_rms_px;
  out.iterations = est.iterations;
  out.quality = quality | est.quality;
  return out;
}

void VoSolverNode::fill_ground_points(const vo::FramePair& pair, int64_t utime) {
  const auto points = depth_map_.trusted_points(options_.solver.feature_depth.max_relative_sigma);
  if (points.empty()) return;
  // From the camera to the INS reference point: camera = INS + R lever (lever_arm.h).
  const Eigen::Vector3d lever =
      rotation_from_rpy(pair.curr_roll, pair.curr_pitch, 0.0) * options_.sync.calibration.camera_lever_arm_m;
  ground_.utime = utime;
  ground_.num_points = static_cast<int32_t>(points.size());
  ground_.track_id.reserve(points.size());
  ground_.position_m.reserve(points.size());
  ground_.depth_sigma_m.reserve(points.size());
  for (const auto& p : points) {
    const Eigen::Vector3d from_ins = p.position + lever;
    ground_.track_id.push_back(p.track_id);
    ground_.position_m.push_back({static_cast<float>(from_ins.x()), static_cast<float>(from_ins.y()),
                                  static_cast<float>(from_ins.z())});
    ground_.depth_sigma_m.push_back(static_cast<float>(p.depth_sigma));
  }
}

void VoSolverNode::publish(const vo_delta_t& delta) {
  if (ground_.num_points > 0 && ground_.utime == delta.utime) {
    bus_.publish(channels::kVoGround, ground_);
    ++ground_published_;
    ground_ = ground_points_t{};
  }
  bus_.publish(channels::kVoDelta, delta);
  ++published_;
  last_published_utime_ = std::max(last_published_utime_, delta.utime);
  last_quality_ = delta.quality;
  last_inliers_ = delta.inliers;
  last_residual_px_ = delta.residual_rms_px;
  if (delta.quality != 0) ++flagged_;
  for (int bit = 0; bit < kQualityBits; ++bit) {
    if (delta.quality & (1 << bit)) ++quality_counts_[bit];
  }
}

StatusReport VoSolverNode::status() const {
  StatusReport r;
  r.received = received_;
  r.published = published_;
  // Old INS/altimeter samples leaving the bounded history are not drops.
  r.dropped = dropped_;
  r.errors = errors_;
  if (last_quality_ != 0) {
    r.state = status_t::STATE_WARN;
    r.detail = "last VO_DELTA flagged: " + vo_quality_names(last_quality_);
  }
  r.counters = {{"pending_frames", static_cast<double>(pending_.size())},
                {"history_evicted", static_cast<double>(sync_.dropped_samples())},
                {"ins_interval_short", static_cast<double>(sync_.short_ins_intervals())},
                {"ins_buffered", static_cast<double>(sync_.ins_samples())},
                {"altimeter_buffered", static_cast<double>(sync_.altimeter_samples())},
                {"altimeter_invalid", static_cast<double>(sync_.invalid_altimeter_samples())},
                {"flagged", static_cast<double>(flagged_)},
                {"late_tracks", static_cast<double>(late_tracks_)},
                {"duplicate_tracks", static_cast<double>(duplicate_tracks_)},
                {"nonfinite_features", static_cast<double>(bad_features_)},
                {"last_inliers", static_cast<double>(last_inliers_)},
                {"last_residual_px", last_residual_px_}};
  if (options_.solver.variant == vo::Variant::kFeatureDepth) {
    r.counters.insert(r.counters.end(), {{"own_depths", static_cast<double>(depth_map_.size())},
                                         {"own_depth_resets", static_cast<double>(depth_map_.resets())},
                                         {"ground_frames_published", static_cast<double>(ground_published_)},
                                         {"own_depths_rejected", static_cast<double>(depth_map_.rejected_depths())},
                                         {"pairs_paper_alone", static_cast<double>(paper_alone_pairs_)},
                                         {"pairs_scale_carried", static_cast<double>(carried_scale_pairs_)}});
  }
  for (int bit = 0; bit < kQualityBits; ++bit) {
    r.counters.emplace_back(std::string("quality_") + vo_quality_name(bit), static_cast<double>(quality_counts_[bit]));
  }
  gate_.add_counters(&r);
  gate_.warn_if_rejecting(&r);
  return r;
}

std::unique_ptr<Node> make_vo_solver_node(const Config& root, Bus& bus) {
  return std::make_unique<VoSolverNode>(VoSolverOptions::from_config(root), bus, InputCheckOptions::from_config(root));
}

void register_vo_solver_node(NodeRegistry& registry) { registry.add("vo_solver", make_vo_solver_node); }

}  // namespace nadir
