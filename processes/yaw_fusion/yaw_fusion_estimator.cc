#include "processes/yaw_fusion/yaw_fusion_estimator.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

#include "common/geometry.h"
#include "processes/yaw_fusion/delta_integration.h"
#include "processes/yaw_fusion/fix_consistency.h"

namespace nadir {

namespace {

constexpr double kUnknownYawVariance = M_PI * M_PI;  // no INS yaw at the first frame
constexpr int64_t kPreStartInsKeepUs = 10'000'000;   // INS kept before the first delta

double square(double v) { return v * v; }

bool all_finite(const vo_delta_t& d) {
  return std::isfinite(d.dx) && std::isfinite(d.dy) && std::isfinite(d.dz) && std::isfinite(d.dyaw);
}

std::string utime_label(const char* channel, int64_t utime) {
  std::ostringstream text;
  text << channel << " utime " << utime << ": ";
  return text.str();
}

}  // namespace

YawFusionEstimator::YawFusionEstimator(const YawFusionOptions& options)
    : options_(options),
      ins_(4096, static_cast<int64_t>(options.ins_min_interval_s * 1e6)),
      sensor_now_(std::numeric_limits<int64_t>::min()),
      vo_jump_candidate_(std::numeric_limits<int64_t>::min()),
      ins_jump_candidate_(std::numeric_limits<int64_t>::min()),
      altimeter_jump_candidate_(std::numeric_limits<int64_t>::min()),
      coast_detector_(options.coast),
      coast_terrain_(options.coast.terrain_window_s),
      seen_ground_(options.coast.seen_ground_window_s),
      horizontal_fix_consistency_(2, options.map_fix_consistency_window),
      vertical_fix_consistency_(1, options.map_fix_consistency_window) {
  options_.Check();
}

bool YawFusionEstimator::plausible_time(int64_t utime, int64_t* candidate, const char* channel) {
  constexpr int64_t kNone = std::numeric_limits<int64_t>::min();
  const int64_t jump = options_.max_time_jump_us();
  if (sensor_now_ == kNone || utime <= sensor_now_ + jump) {
    *candidate = kNone;
    return true;
  }
  if (*candidate != kNone && std::abs(utime - *candidate) <= jump) {
    *candidate = kNone;  // two messages in a row agree: the time base really jumped
    return true;
  }
  // One corrupted timestamp must not push sensor time (and every wait and gap
  // decision) far ahead: drop it, remember it in case the next one agrees.
  *candidate = utime;
  ++counters_.time_jumps_dropped;
  note_problem(utime_label(channel, utime) + "more than max_time_jump_s ahead of all other sensor time, dropped");
  return false;
}

bool YawFusionEstimator::vo_lost() const {
  return started_ && sensor_now_ - last_good_utime_ > static_cast<int64_t>(options_.gap_max_duration_s * 1e6);
}

std::vector<pose_t> YawFusionEstimator::add_vo_delta(const vo_delta_t& delta) {
  ++counters_.vo_deltas_received;
  std::vector<pose_t> out;
  const int64_t interval = delta.utime - delta.prev_utime;
  if (delta.prev_utime <= 0) return out;  // the first frame: no motion yet, nothing wrong
  // A delta coasted over (not integrated) may span any time: the tracker
  // measures from its last good frame while the texture is gone.
  const bool coasted = options_.coast.enabled && (delta.quality & options_.coast.quality_mask) != 0;
  // Nor may one from the last integrated frame that can bridge a coast (bridges_coast).
  const bool bridging = may_bridge_a_coast(delta);
  if (interval <= 0 ||
      (interval > static_cast<int64_t>(options_.max_delta_interval_s * 1e6) && !coasted && !bridging)) {
    ++counters_.vo_deltas_invalid;
    note_problem(utime_label("VO_DELTA", delta.utime) + "prev_utime " + std::to_string(delta.prev_utime) +
                 " gives an interval outside (0, max_delta_interval_s]");
    return out;
  }
  if (!plausible_time(delta.utime, &vo_jump_candidate_, "VO_DELTA")) return out;
  if (started_ && delta.utime <= last_frame_utime_) {
    ++counters_.vo_deltas_late;
    note_problem(utime_label("VO_DELTA", delta.utime) + "arrived after that frame time was published");
    return out;
  }
  if (!pending_.emplace(delta.utime, delta).second) {
    ++counters_.vo_deltas_duplicate;
    note_problem(utime_label("VO_DELTA", delta.utime) + "duplicate frame time, ignored");
    return out;
  }
  sensor_now_ = std::max(sensor_now_, delta.utime);
  pump(&out);
  return out;
}

std::vector<pose_t> YawFusionEstimator::add_ins(const ins_t& ins) {
  ++counters_.ins_received;
  std::vector<pose_t> out;
  if (ins.utime <= 0 || !std::isfinite(ins.roll) || !std::isfinite(ins.pitch) || !std::isfinite(ins.yaw) ||
      std::abs(ins.roll) > M_PI || std::abs(ins.pitch) > M_PI_2 || std::abs(ins.yaw) > 2.0 * M_PI) {
    ++counters_.ins_invalid;
    note_problem(utime_label("INS", ins.utime) + "non-finite or out-of-range attitude (or utime <= 0)");
    return out;
  }
  if (!plausible_time(ins.utime, &ins_jump_candidate_, "INS")) return out;
  AttitudeSample sample;
  sample.utime = ins.utime;
  sample.roll = ins.roll;
  sample.pitch = ins.pitch;
  sample.yaw = wrap_angle(ins.yaw);
  sample.body_rate = Eigen::Vector3d(ins.angular_rate[0], ins.angular_rate[1], ins.angular_rate[2]);
  sample.has_rate = ins.has_rates && sample.body_rate.allFinite();
  if (!sample.has_rate) sample.body_rate.setZero();
  double stddev = deg_to_rad(options_.ins_yaw_stddev_deg);
  if (ins.has_stddev && std::isfinite(ins.attitude_stddev[2]) && ins.attitude_stddev[2] > 0.0) {
    stddev = ins.attitude_stddev[2];
  }
  sample.yaw_variance = stddev > deg_to_rad(options_.max_ins_yaw_stddev_deg) ? -1.0 : square(stddev);
  if (!ins_.add(sample)) {
    ++counters_.ins_duplicate;
    return out;
  }
  sensor_now_ = std::max(sensor_now_, ins.utime);
  pump(&out);
  return out;
}

void YawFusionEstimator::add_ground_points(const ground_points_t& points) {
  ++counters_.ground_frames_received;
  if (!options_.coast.follow_seen_ground || (started_ && points.utime <= last_good_utime_)) return;
  pending_ground_[points.utime] = points;
  // Bounded: frames whose delta never comes (not solved, dropped) do not pile up.
  constexpr size_t kMaxPendingGround = 64;
  while (pending_ground_.size() > kMaxPendingGround) pending_ground_.erase(pending_ground_.begin());
}

std::vector<pose_t> YawFusionEstimator::add_altimeter(const altimeter_t& altimeter) {
  ++counters_.altimeter_received;
  std::vector<pose_t> out;
  if (altimeter.utime <= 0) {
    ++counters_.altimeter_invalid;
    note_problem(utime_label("ALTIMETER", altimeter.utime) + "utime <= 0");
    return out;
  }
  if (!plausible_time(altimeter.utime, &altimeter_jump_candidate_, "ALTIMETER")) return out;
  const Eigen::Vector3d beam(altimeter.beam_body[0], altimeter.beam_body[1], altimeter.beam_body[2]);
  const double range_m = options_.calibration.true_range(altimeter.range_m);
  const bool usable = altimeter.validity == altimeter_t::VALID_OK && std::isfinite(range_m) && range_m > 0.0 &&
                      beam.allFinite() && beam.norm() > 0.5 && beam.norm() < 1.5;
  if (usable) {
    RangeSample sample;
    sample.utime = altimeter.utime;
    // Heights are the INS reference point's, above the point the beam hit.
    const AltimeterRay ray = options_.calibration.ray_from(Eigen::Vector3d::Zero(), altimeter.range_m, beam.normalized());
    sample.range_m = ray.range_m;
    sample.beam_body = ray.beam_body;
    altimeter_.add(sample);
  } else {
    ++counters_.altimeter_invalid;
    altimeter_.note_time(altimeter.utime);
  }
  sensor_now_ = std::max(sensor_now_, altimeter.utime);
  pump(&out);
  return out;
}

std::optional<AttitudeSample> YawFusionEstimator::ins_attitude_at(int64_t utime) const {
  return ins_.at(options_.calibration.exposure_utime(utime), static_cast<int64_t>(options_.max_ins_bracket_s * 1e6),
                 options_.attitude_policy);
}

FrameAttitudeNoise YawFusionEstimator::frame_attitude_noise(int64_t utime) const {
  FrameAttitudeNoise frame;
  if (const auto attitude = ins_attitude_at(utime)) {
    frame.pitch = attitude->pitch;
    frame.noise_share = attitude->white_noise_share;
  }
  return frame;
}

bool YawFusionEstimator::delta_ready(const vo_delta_t& delta) const {
  const int64_t t = options_.calibration.exposure_utime(delta.utime);  // when the sensors are read
  if (sensor_now_ >= t + options_.ins_wait_us()) return true;
  if (static_cast<int>(pending_.size()) > options_.max_pending_deltas) return true;
  const bool ins_complete = propagates(options_.attitude_policy, ins_.newest_has_rate()) ? ins_.complete_at(t)
                                                                                        : ins_.newest_utime() >= t;
  if (!ins_complete) return false;
  if (!options_.altimeter_interpolate) return true;
  return altimeter_.newest_utime() >= t || sensor_now_ >= t + options_.altimeter_wait_us();
}

void YawFusionEstimator::pump(std::vector<pose_t>* out) {
  const size_t poses_before = out->size();
  const int64_t period = options_.frame_period_us();
  const int64_t tolerance = static_cast<int64_t>(options_.frame_time_tolerance_s * 1e6);
  const int64_t max_gap = static_cast<int64_t>(options_.gap_max_duration_s * 1e6);
  // A gap pose at t is due when no delta covers t: deltas arrive in order on
  // their own channel, so only the first pending one can.
  auto gap_due = [&](int64_t t) {
    if (t - last_good_utime_ > max_gap) return false;
    return pending_.empty() || pending_.begin()->second.prev_utime > t + period / 2;
  };
  auto emit_gap_pose = [&](int64_t t) {
    int32_t flags = pose_t::FLAG_VO_GAP | advance_without_vo(t);
    flags |= apply_due_map_fixes(t);
    const double fallback = have_height_ ? height_agl_ : std::numeric_limits<double>::quiet_NaN();
    flags |= update_height(t, fallback);
    out->push_back(make_pose(t, flags));
    ++counters_.gap_poses;
  };
  while (true) {
    if (!pending_.empty()) {
      const vo_delta_t& next = pending_.begin()->second;
      const bool bridge = started_ && bridges_coast(next);
      if (started_ && (bridge || supersedes_gap_poses(next))) {
        filter_ = good_filter_;
        consecutive_altimeter_rejections_ = good_consecutive_altimeter_rejections_;
        last_altimeter_height_ = good_altimeter_height_;
        last_frame_utime_ = last_good_utime_;
        yaw_without_vo_ = false;  // back to the yaw the delta continues from
        if (bridge) {
          // Integrated in the coast's place, with the coast's horizontal (from that yaw on).
          next_bridge_ = bridge_delta(next);
          coasting_ = false;
          ++counters_.coasts_bridged;
        } else {
          ++counters_.gap_poses_superseded;
        }
      }
      // Texture lost, the tracker keeps measuring from its last good frame:
      // deltas to be coasted over that start before the last pose still
      // move time on (coasted to their utime), they are not late.
      const bool coast_overlap = options_.coast.enabled && (next.quality & options_.coast.quality_mask) != 0;
      if (started_ && (next.utime <= last_frame_utime_ ||
                       (next.prev_utime < last_frame_utime_ - tolerance && !coast_overlap))) {
        ++counters_.vo_deltas_late;
        note_problem(utime_label("VO_DELTA", next.utime) + "overlaps poses already published, dropped");
        pending_.erase(pending_.begin());
        continue;
      }
      if (delta_ready(next)) {
        if (started_ && gap_due(last_frame_utime_ + period)) {
          emit_gap_pose(last_frame_utime_ + period);
          continue;
        }
        const vo_delta_t delta = next_bridge_ && next_bridge_->utime == next.utime ? *next_bridge_ : next;
        next_bridge_.reset();
        pending_.erase(pending_.begin());
        if (!started_) {
          if (!delta_usable(delta)) {
            ++counters_.vo_deltas_before_start;
            continue;
          }
          start(delta, out);
        }
        const int32_t fix_flags = apply_due_map_fixes(delta.utime);
        const size_t before = out->size();
        process_delta(delta, out);
        if (fix_flags != 0 && out->size() > before) out->back().flags |= fix_flags;
        continue;
      }
      if (!started_) break;
    }
    if (started_) {
      const int64_t t = last_frame_utime_ + period;
      if (gap_due(t) && sensor_now_ >= options_.calibration.exposure_utime(t) + options_.ins_wait_us()) {
        emit_gap_pose(t);
        continue;
      }
    }
    break;
  }
  counters_.poses += static_cast<int64_t>(out->size() - poses_before);
  remember_poses(*out, poses_before);
  if (started_) {
    // Keep what any later query can touch (queries are at or after the last
    // frame's exposure, or the last good frame's when a delta supersedes the
    // gap poses after it and coasts from there), so how many frames one call
    // processes -- which depends on arrival order -- cannot change an answer.
    const int64_t last_exposure = options_.calibration.exposure_utime(std::min(last_frame_utime_, last_good_utime_));
    altimeter_.forget_before(last_exposure - static_cast<int64_t>(
                                                 std::max(options_.max_altimeter_age_s, options_.coast.max_range_age_s) * 1e6));
    ins_.forget_before(last_exposure);
  } else {
    ins_.forget_before(sensor_now_ - kPreStartInsKeepUs);
    altimeter_.forget_before(sensor_now_ - kPreStartInsKeepUs);
  }
}

bool YawFusionEstimator::supersedes_gap_poses(const vo_delta_t& delta) const {
  const int64_t tolerance = static_cast<int64_t>(options_.frame_time_tolerance_s * 1e6);
  // At the camera rate a delta over a gap long enough for gap poses (ins_wait_s)
  // carries QUALITY_FRAME_GAP from the solver (max_frame_interval_ms): those
  // keep being dropped, the 14 Hz behaviour is unchanged.
  return last_good_utime_ < last_frame_utime_ && delta.utime > last_frame_utime_ &&
         std::abs(delta.prev_utime - last_good_utime_) <= tolerance &&
         (delta.quality & vo_delta_t::QUALITY_FRAME_GAP) == 0;
}

bool YawFusionEstimator::may_bridge_a_coast(const vo_delta_t& delta) const {
  if (!options_.coast.enabled || !options_.coast.bridge || !started_) return false;
  const int64_t tolerance = static_cast<int64_t>(options_.frame_time_tolerance_s * 1e6);
  return std::abs(delta.prev_utime - last_good_utime_) <= tolerance &&
         static_cast<double>(delta.utime - delta.prev_utime) * 1e-6 <= options_.coast.max_duration_s;
}

bool YawFusionEstimator::bridges_coast(const vo_delta_t& delta) const {
  std::string why;
  return coasting_ && may_bridge_a_coast(delta) && delta.utime > last_frame_utime_ && delta_quality_ok(delta) &&
         (delta.quality & options_.coast.quality_mask) == 0 && delta_values_valid(delta, &why);
}

std::optional<YawFusionEstimator::Turn> YawFusionEstimator::ins_turn(int64_t from, int64_t to) const {
  const int64_t bracket = static_cast<int64_t>(options_.max_ins_bracket_s * 1e6);
  const auto a = ins_.at(options_.calibration.exposure_utime(from), bracket, AttitudePolicy::kInterpolate);
  const auto b = ins_.at(options_.calibration.exposure_utime(to), bracket, AttitudePolicy::kInterpolate);
  if (!a || !b || a->yaw_variance < 0.0 || b->yaw_variance < 0.0) return std::nullopt;
  const double span_s = static_cast<double>(to - from) * 1e-6;
  return Turn{angle_difference(b->yaw, a->yaw),
              a->yaw_variance + b->yaw_variance +
                  square(deg_to_rad(options_.ins_yaw_bias_walk_deg_per_sqrt_s)) * std::max(0.0, span_s)};
}

namespace {

// A VO_DELTA's covariance (dx, dy, dz, dyaw, ground roll, ground pitch) in place.
using DeltaCovariance = Eigen::Map<Eigen::Matrix<double, 6, 6, Eigen::RowMajor>>;

// The delta as if its dyaw had been measured as `dyaw` with `variance`.
void condition_on_heading_change(double dyaw, double variance, vo_delta_t* delta) {
  DeltaCovariance covariance(&delta->covariance[0][0]);
  const double own = covariance(3, 3);
  // The horizontal step's regression on dyaw (1 for dyaw itself): moved by
  // the difference, its variance the part dyaw did not explain plus what the
  // INS's turn leaves. Not the climb: the solver's dz is the mean of the
  // forward and the time-reversed solve, in which a dyaw error cancels, while
  // its covariance row is the forward solve's. Nor the ground tilt.
  Eigen::Matrix<double, 6, 1> regression = Eigen::Matrix<double, 6, 1>::Unit(3);
  if (own > 0.0) {
    regression(0) = covariance(0, 3) / own;
    regression(1) = covariance(1, 3) / own;
  }
  const double difference = angle_difference(dyaw, delta->dyaw);
  delta->dx += regression(0) * difference;
  delta->dy += regression(1) * difference;
  delta->dyaw = dyaw;
  covariance += regression * regression.transpose() * (variance - own);
}

}  // namespace

vo_delta_t YawFusionEstimator::bridge_delta(const vo_delta_t& delta) const {
  vo_delta_t bridged = delta;
  if (options_.coast.bridge_heading_from_ins) {
    if (const auto turn = ins_turn(last_good_utime_, delta.utime)) {
      condition_on_heading_change(turn->dyaw, turn->variance, &bridged);
    }
  }
  const BridgeHorizontal source = options_.coast.bridge_horizontal;
  if (source == BridgeHorizontal::kPair) return bridged;
  // The held velocity over the span (the heading the INS measured along the
  // way), in the level frame of the last integrated frame the delta starts
  // from, with the coast model's variance; the climb and ground tilt stay the
  // delta's.
  Eigen::Vector3d velocity_at_end;
  const Eigen::Vector3d level_velocity(coast_velocity_level_.x(), coast_velocity_level_.y(), 0.0);
  const Eigen::Vector3d world = coast_displacement(last_good_utime_, delta.utime, level_velocity, &velocity_at_end);
  const Eigen::Vector2d coast = (rotation_from_rpy(0.0, 0.0, -good_filter_.yaw()) * world).head<2>();
  const double span_s = static_cast<double>(delta.utime - last_good_utime_) * 1e-6;
  const double variance =
      coast_position_variance(options_.coast.velocity_stddev_mps, options_.coast.velocity_random_walk, span_s);
  Eigen::Matrix2d covariance = Eigen::Matrix2d::Identity() * variance;
  Eigen::Vector2d horizontal = coast;
  const Eigen::Vector2d pair(bridged.dx, bridged.dy);
  if (source == BridgeHorizontal::kPairDirection && pair.norm() > 0.0 && coast.norm() > 0.0) {
    // A single-plane solve across the coast is off in scale (the ground at
    // the images' edges against the range at the nadir), not in direction;
    // the held velocity is off in direction (the heading's swing about the
    // track), not in length. The pair's direction, the coast's length; along
    // it the coast's variance, across it the pair's, scaled to that length.
    const Eigen::Vector2d along = pair.normalized();
    const Eigen::Vector2d across(-along.y(), along.x());
    const Eigen::Matrix2d pair_covariance = DeltaCovariance(&bridged.covariance[0][0]).topLeftCorner<2, 2>();
    const double scale = coast.norm() / pair.norm();
    horizontal = along * coast.norm();
    covariance = variance * along * along.transpose() +
                 scale * scale * across.dot(pair_covariance * across) * across * across.transpose();
  }
  bridged.dx = horizontal.x();
  bridged.dy = horizontal.y();
  DeltaCovariance out(&bridged.covariance[0][0]);
  out.topRows<2>().setZero();
  out.leftCols<2>().setZero();
  out.topLeftCorner<2, 2>() = covariance;
  return bridged;
}

yaw_fusion_checkpoint_t YawFusionEstimator::checkpoint(const pose_t& pose) const {
  yaw_fusion_checkpoint_t out = checkpoint_without_bias(pose);
  const PoseFilter::YawBiasState bias = filter_.yaw_bias_state();
  out.has_heading_bias = true;
  out.heading_bias_estimated = bias.estimated;
  for (int i = 0; i < 2; ++i) {
    out.heading_bias_rad[i] = bias.estimate(i);
    for (int j = 0; j < 2; ++j) {
      out.heading_bias_covariance[i][j] = bias.covariance(i, j);
      out.heading_bias_prior_covariance[i][j] = bias.prior_covariance(i, j);
    }
  }
  return out;
}

bool YawFusionEstimator::resume(int64_t t0) {
  const yaw_fusion_checkpoint_t saved = *resume_;
  const pose_t& last = saved.pose;
  resume_.reset();
  const double dt = static_cast<double>(t0 - last.utime) * 1e-6;
  if (dt < 0.0 || dt > options_.gap_max_duration_s) {
    note_problem("checkpoint POSE utime " + std::to_string(last.utime) + " is " + std::to_string(dt) +
                 " s from the first delta (allowed 0 .. gap.max_duration_s): not resumed, new origin");
    return false;
  }
  const Eigen::Vector3d velocity(last.velocity_ned[0], last.velocity_ned[1], last.velocity_ned[2]);
  Eigen::Vector3d position(last.position_ned[0], last.position_ned[1], last.position_ned[2]);
  Eigen::Matrix3d covariance;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) covariance(i, j) = last.position_covariance[i][j];
  }
  if (!position.allFinite() || !velocity.allFinite() || !covariance.allFinite() || !std::isfinite(last.yaw) ||
      !std::isfinite(last.yaw_variance)) {
    note_problem("checkpoint POSE utime " + std::to_string(last.utime) + " holds non-finite values: new origin");
    return false;
  }
  // As a VO gap: dead-reckon with the last velocity, grow the uncertainty
  // as if that velocity were off by gap.velocity_stddev_mps throughout.
  position += velocity * std::min(dt, options_.gap_max_propagation_s);
  covariance += Eigen::Matrix3d::Identity() * square(options_.gap_velocity_stddev_mps * dt);
  const double yaw_variance = last.yaw_variance + square(deg_to_rad(options_.gap_yaw_rate_stddev_dps) * dt);
  filter_.restore(position, covariance, last.yaw, yaw_variance);
  if (saved.has_heading_bias) {
    PoseFilter::YawBiasState bias;
    bias.estimated = saved.heading_bias_estimated;
    for (int i = 0; i < 2; ++i) {
      bias.estimate(i) = saved.heading_bias_rad[i];
      for (int j = 0; j < 2; ++j) {
        bias.covariance(i, j) = saved.heading_bias_covariance[i][j];
        bias.prior_covariance(i, j) = saved.heading_bias_prior_covariance[i][j];
      }
    }
    const bool usable = bias.estimate.allFinite() && bias.covariance.allFinite() &&
                        bias.prior_covariance.allFinite() && bias.covariance.diagonal().minCoeff() >= 0.0 &&
                        bias.prior_covariance.diagonal().minCoeff() >= 0.0;
    if (!usable) {
      note_problem("checkpoint POSE utime " + std::to_string(last.utime) +
                   " holds a heading bias that is not finite or has a negative variance: the bias starts again "
                   "from its prior");
    } else {
      filter_.restore_yaw_bias(bias);
    }
  }
  velocity_out_ = velocity;
  last_velocity_ = velocity;
  frames_ = last.frames;
  yaw_from_ins_ = (last.flags & pose_t::FLAG_INITIALIZING) == 0;
  ++counters_.resumed;
  return true;
}

void YawFusionEstimator::start(const vo_delta_t& first, std::vector<pose_t>* out) {
  const int64_t t0 = first.prev_utime;
  const auto attitude = ins_attitude_at(t0);
  // A resumed run continues the previous one's frame (flagged as a gap);
  // otherwise this frame is the origin.
  const bool resumed = resume_ && resume(t0);
  if (!resumed && attitude && attitude->yaw_variance >= 0.0) {
    filter_.initialise(attitude->yaw, attitude->yaw_variance);
    yaw_from_ins_ = true;
  } else if (!resumed) {
    // Heading unknown: integrate in an arbitrary frame, flagged initialising,
    // until an INS yaw arrives (it passes any gate against this variance).
    filter_.initialise(0.0, kUnknownYawVariance);
    ++counters_.ins_yaw_unusable;
  }
  int32_t flags = resumed ? static_cast<int32_t>(pose_t::FLAG_VO_GAP) : static_cast<int32_t>(pose_t::FLAG_INITIALIZING);
  if (attitude) {
    roll_ = attitude->roll;
    pitch_ = attitude->pitch;
  }
  started_ = true;
  last_frame_utime_ = t0;
  last_good_utime_ = t0;
  flags |= update_height(t0, std::numeric_limits<double>::quiet_NaN());
  if (options_.coast.follow_altimeter) {
    coast_terrain_.note_frame(t0, filter_.position(), last_altimeter_height_,
                              Eigen::Vector2d::Constant(std::numeric_limits<double>::quiet_NaN()));
  }
  good_filter_ = filter_;
  good_consecutive_altimeter_rejections_ = consecutive_altimeter_rejections_;
  good_altimeter_height_ = last_altimeter_height_;
  out->push_back(make_pose(t0, flags));
}

bool YawFusionEstimator::delta_values_valid(const vo_delta_t& delta, std::string* why) const {
  if (!all_finite(delta)) {
    *why = "non-finite dx/dy/dz/dyaw";
    return false;
  }
  // Any heading change between frames is possible (a 180 deg turn between the
  // photos of a survey); the solver publishes it wrapped to [-180, 180] deg.
  // The INS rate limits of input_checks judge whether it is plausible.
  if (std::abs(delta.dyaw) > M_PI + 1e-9) {
    *why = "dyaw outside [-180, 180] deg (not wrapped)";
    return false;
  }
  Eigen::Matrix4d cov;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) cov(r, c) = delta.covariance[r][c];
  }
  if (!cov.allFinite()) {
    *why = "non-finite covariance";
    return false;
  }
  // Variances of 1e12 (a 1000 km sigma) carry no information and overflow the
  // filter's products: such a delta is as unusable as a non-finite one.
  if (cov.cwiseAbs().maxCoeff() > 1e12) {
    *why = "covariance over (dx, dy, dz, dyaw) larger than 1e12";
    return false;
  }
  const Eigen::Matrix4d sym = 0.5 * (cov + cov.transpose());
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> eig(sym, Eigen::EigenvaluesOnly);
  const double largest = std::max(1e-30, eig.eigenvalues().cwiseAbs().maxCoeff());
  if (eig.eigenvalues().minCoeff() < -1e-9 * largest) {
    *why = "covariance over (dx, dy, dz, dyaw) is not positive semi-definite";
    return false;
  }
  return true;
}

void YawFusionEstimator::process_delta(const vo_delta_t& delta, std::vector<pose_t>* out) {
  int32_t flags = 0;
  const int64_t tolerance = static_cast<int64_t>(options_.frame_time_tolerance_s * 1e6);
  if (delta.prev_utime > last_frame_utime_ + tolerance) {
    // The delta(s) before this one are missing: dead-reckon to its start so
    // it is registered with the yaw at its own previous frame, and publish
    // that (real) frame too, flagged. While coasting (the tracker restarting
    // after texture loss) the coast goes on over it.
    const bool coast_on = coasting_ && static_cast<double>(delta.prev_utime - last_good_utime_) * 1e-6 <=
                                           options_.coast.max_duration_s;
    int32_t bridge_flags = coast_on ? pose_t::FLAG_COASTING | coast_to(delta.prev_utime)
                                    : pose_t::FLAG_VO_GAP | advance_without_vo(delta.prev_utime);
    bridge_flags |= update_height(delta.prev_utime, have_height_ ? height_agl_ : std::numeric_limits<double>::quiet_NaN());
    out->push_back(make_pose(delta.prev_utime, bridge_flags));
    ++counters_.gap_bridges;
    ++counters_.gap_poses;
  }
  const double held_height = have_height_ ? height_agl_ : std::numeric_limits<double>::quiet_NaN();
  // Not integrated: bridged as a VO gap (dead-reckoned, then held).
  auto publish_gap = [&]() {
    recent_positions_.clear();
    coast_positions_.clear();
    coast_terrain_.clear();
    seen_ground_.clear();
    recent_ranges_.clear();
    flags |= pose_t::FLAG_VO_GAP | advance_without_vo(delta.utime);
    flags |= update_height(delta.utime, held_height);
    out->push_back(make_pose(delta.utime, flags));
  };
  std::string why;
  const bool valid = delta_values_valid(delta, &why);
  const int32_t coasted_bits = coast_bits(delta);
  const bool coast_quality = coasted_bits != 0;
  const bool quality_ok = delta_quality_ok(delta);
  if (!valid) {
    ++counters_.vo_deltas_invalid;
    note_problem(utime_label("VO_DELTA", delta.utime) + why);
    publish_gap();
    return;
  }
  if (!quality_ok && !coast_quality) {
    ++counters_.vo_deltas_quality_rejected;
    publish_gap();
    return;
  }
  const int32_t reason = coast_reason(delta, coasted_bits);
  if (reason != 0) {
    ++counters_.vo_deltas_coasted;
    for (int bit = 0; bit < kCoastReasons; ++bit) {
      if (reason & (1 << bit)) ++counters_.coast_reasons[bit];
    }
    if (static_cast<double>(delta.utime - last_good_utime_) * 1e-6 > options_.coast.max_duration_s) {
      ++counters_.coast_expired;  // coasted too long: a VO gap as without coasting
      publish_gap();
      return;
    }
    const bool scale_only = reason == kCoastQuality && quality_ok &&
                            coasted_bits == vo_delta_t::QUALITY_STALE_ALTIMETER &&
                            (delta.quality & vo_delta_t::QUALITY_HIGH_RESIDUAL) == 0;
    const bool continuous = std::abs(delta.prev_utime - last_frame_utime_) <= tolerance;
    flags |= pose_t::FLAG_COASTING |
             coast_to(delta.utime, options_.coast.vo_direction && scale_only && continuous ? &delta : nullptr);
    flags |= update_height(delta.utime, held_height);
    out->push_back(make_pose(delta.utime, flags));
    return;
  }
  if (ins_.newest_utime() < options_.calibration.exposure_utime(delta.utime)) ++counters_.vo_deltas_without_ins;

  Eigen::Matrix4d cov;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) cov(r, c) = 0.5 * (delta.covariance[r][c] + delta.covariance[c][r]);
  }
  for (int i = 0; i < 3; ++i) cov(i, i) = std::max(cov(i, i), square(options_.min_translation_stddev_m));
  cov(3, 3) = std::max(cov(3, 3), square(deg_to_rad(options_.min_dyaw_stddev_deg)));

  const PoseFilter before = filter_;
  const Eigen::Vector3d world =
      integrate_delta(&filter_, delta, cov, frame_attitude_noise(delta.prev_utime), frame_attitude_noise(delta.utime),
                      options_);
  if (!world.allFinite() || !filter_.position().allFinite() || !filter_.covariance().allFinite()) {
    // Finite but extreme values overflowed: nothing non-finite is ever published.
    filter_ = before;
    ++counters_.deltas_reverted;
    ++counters_.vo_deltas_invalid;
    note_problem(utime_label("VO_DELTA", delta.utime) + "integrating it overflows the state, not used");
    publish_gap();
    return;
  }
  coasting_ = false;
  coast_detector_.note_integrated(delta);
  const double dt = static_cast<double>(delta.utime - delta.prev_utime) * 1e-6;
  last_velocity_ = world / dt;
  recent_positions_.emplace_back(delta.utime, filter_.position());
  const int64_t window_us = static_cast<int64_t>(options_.velocity_window_s * 1e6);
  while (recent_positions_.size() > 2 && delta.utime - recent_positions_[1].first >= window_us) {
    recent_positions_.pop_front();
  }
  if (recent_positions_.size() >= 2 && recent_positions_.front().first < delta.utime) {
    const auto& oldest = recent_positions_.front();
    last_velocity_ = (filter_.position() - oldest.second) / (static_cast<double>(delta.utime - oldest.first) * 1e-6);
  }
  velocity_out_ = last_velocity_;
  last_frame_utime_ = delta.utime;
  last_good_utime_ = delta.utime;
  ++frames_;
  ++counters_.vo_deltas_integrated;

  flags |= update_attitude(delta.utime);
  // The yaw the next delta is registered with (the INS update does not move the position).
  coast_positions_.push_back(CoastSample{delta.utime, filter_.position(), filter_.yaw()});
  const int64_t coast_window_us = static_cast<int64_t>(options_.coast.speed_window_s * 1e6);
  while (coast_positions_.size() > 2 && delta.utime - coast_positions_[1].utime >= coast_window_us) {
    coast_positions_.pop_front();
  }
  double fallback = std::numeric_limits<double>::quiet_NaN();
  if (std::isfinite(delta.altitude_m) && delta.altitude_m > 0.0) {
    fallback = delta.altitude_m - delta.dz;  // height at the previous frame, minus the descent
  } else if (have_height_) {
    fallback = height_agl_ - world.z();
  }
  flags |= update_height(delta.utime, fallback);
  if (options_.coast.follow_altimeter) {  // the ground plane is only ever anchored then
    coast_terrain_.note_frame(delta.utime, filter_.position(), last_altimeter_height_,
                              ground_gradient_ned(delta.ground_roll, delta.ground_pitch, filter_.yaw()));
  }
  if (options_.coast.follow_seen_ground) {
    // This frame's points, each replacing its track's older one.
    const auto points = pending_ground_.find(delta.utime);
    if (points != pending_ground_.end()) {
      seen_ground_.note_frame(points->second, filter_.position(), filter_.yaw());
    } else {
      seen_ground_.note_frame_without_points(delta.utime);
    }
    pending_ground_.erase(pending_ground_.begin(), pending_ground_.upper_bound(delta.utime));
    // The ranges measured since the previous frame, where the vehicle was then (the anchor's).
    for (const PlacedRange& r : place_ranges(delta.prev_utime, delta.utime, filter_.position(), last_velocity_)) {
      recent_ranges_.push_back(r);
    }
    const int64_t seen_window_us = static_cast<int64_t>(options_.coast.seen_ground_window_s * 1e6);
    while (!recent_ranges_.empty() && recent_ranges_.front().utime < recent_ranges_.back().utime - seen_window_us) {
      recent_ranges_.pop_front();
    }
  }
  good_filter_ = filter_;
  good_consecutive_altimeter_rejections_ = consecutive_altimeter_rejections_;
  good_altimeter_height_ = last_altimeter_height_;
  out->push_back(make_pose(delta.utime, flags));
}

int32_t YawFusionEstimator::advance_without_vo(int64_t utime) {
  if (utime <= last_frame_utime_) return 0;
  const double max_prop = options_.gap_max_propagation_s;
  const double e0 = static_cast<double>(last_frame_utime_ - last_good_utime_) * 1e-6;
  const double e1 = static_cast<double>(utime - last_good_utime_) * 1e-6;
  const double dead_reckoned = std::max(0.0, std::min(e1, max_prop) - e0);
  const Eigen::Vector3d displacement = last_velocity_ * dead_reckoned;
  // Position error after e seconds of gap: the last velocity off by
  // sigma_v for the dead-reckoned part, then by |v| + sigma_v while holding.
  const double sigma_v = options_.gap_velocity_stddev_mps;
  const double sigma_hold = sigma_v + last_velocity_.norm();
  auto position_sigma = [&](double e) {
    return e <= max_prop ? sigma_v * e : sigma_v * max_prop + sigma_hold * (e - max_prop);
  };
  const double position_var = square(position_sigma(e1)) - square(position_sigma(e0));
  const double yaw_rate_sigma = deg_to_rad(options_.gap_yaw_rate_stddev_dps);
  const double yaw_var = square(yaw_rate_sigma) * (e1 * e1 - e0 * e0);
  filter_.propagate_without_vo(displacement, Eigen::Vector3d::Constant(position_var), yaw_var);
  velocity_out_ = e1 <= max_prop ? last_velocity_ : Eigen::Vector3d::Zero();
  last_frame_utime_ = utime;
  // The predicted yaw is the last one held constant: a turn flown in the gap
  // (a photo survey's line reversal, an unsolved pair) would otherwise leave
  // the INS yaw outside the gate for max_consecutive_yaw_rejections updates.
  yaw_without_vo_ = true;
  return update_attitude(utime);
}

int32_t YawFusionEstimator::coast_to(int64_t utime, const vo_delta_t* direction) {
  if (!coasting_) {
    // The velocity of the last integrated frames, held in the level vehicle
    // frame from here on: a turn the INS measures turns it too.
    coasting_ = true;
    ++counters_.coast_episodes;
    recent_positions_.clear();
    // Over the speed window when there is one (held_level_velocity), else the published velocity.
    coast_velocity_level_ = held_level_velocity(coast_positions_)
                                .value_or(rotation_from_rpy(0.0, 0.0, -good_filter_.yaw()) * last_velocity_);
    const bool seen_ground_below = anchor_seen_ground();
    coast_positions_.clear();
    if (options_.coast.follow_altimeter) {
      coast_terrain_.anchor();
    } else {
      coast_terrain_.release();
    }
    const CoastOptions& c = options_.coast;
    CoastVerticalModes::Options modes;
    modes.steady = {c.seen_ground_steady_climb_stddev_mps, c.seen_ground_steady_random_walk};
    modes.changing = {c.vertical_velocity_stddev_mps, c.velocity_random_walk};
    // Without seen ground nothing would tell the models apart: the coast model alone.
    modes.changing_probability = seen_ground_below ? c.seen_ground_changing_probability : 1.0;
    modes.switch_rate_per_s = seen_ground_below ? c.seen_ground_switch_rate : 0.0;
    coast_vertical_.start(good_filter_.position().z(), coast_velocity_level_.z(), modes);
    on_seen_ground_ = false;
    last_range_utime_ = recent_ranges_.empty() ? 0 : recent_ranges_.back().utime;
  }
  if (utime <= last_frame_utime_) return 0;
  const double e0 = static_cast<double>(last_frame_utime_ - last_good_utime_) * 1e-6;
  const double e1 = static_cast<double>(utime - last_good_utime_) * 1e-6;
  // The climb as the height filter has it (the held one, or the one measured over seen ground).
  Eigen::Vector3d level_velocity(coast_velocity_level_.x(), coast_velocity_level_.y(), coast_vertical_.climb());
  const double speed = coast_velocity_level_.head<2>().norm();
  const double step = direction != nullptr ? std::hypot(direction->dx, direction->dy) : 0.0;
  std::optional<double> direction_climb;
  if (step > 1e-6 && speed > 0.0) {
    // Right direction, wrong scale (a stale range): the held speed along it.
    const double climb = std::clamp(direction->dz / step, -options_.coast.max_climb_ratio,
                                    options_.coast.max_climb_ratio);
    level_velocity = Eigen::Vector3d(direction->dx / step, direction->dy / step, climb) * speed;
    direction_climb = climb * speed;
  }
  Eigen::Vector3d velocity = rotation_from_rpy(0.0, 0.0, filter_.yaw()) * level_velocity;
  // The held velocity along the heading the INS measured over the step; a
  // direction's delta is in the previous frame's level frame, as it was.
  const Eigen::Vector3d displacement = direction_climb
                                           ? Eigen::Vector3d(velocity * (e1 - e0))
                                           : coast_displacement(last_frame_utime_, utime, level_velocity, &velocity);
  const CoastOptions& c = options_.coast;
  // Variance grown over [e0, e1] of the coast (coast_position_variance).
  const double horizontal = coast_position_variance(c.velocity_stddev_mps, c.velocity_random_walk, e1) -
                            coast_position_variance(c.velocity_stddev_mps, c.velocity_random_walk, e0);
  // The height filter to e1 (coast_vertical_modes.h), with the ranges over
  // seen ground; the vertical variance grows as it does (over seen ground
  // its own down replaces the pose's below).
  const double vertical_before = coast_vertical_.down_variance();
  bool over_seen_ground = false;
  if (options_.coast.follow_seen_ground) {
    over_seen_ground = follow_seen_ground(utime, filter_.position() + displacement, velocity, e0, direction_climb);
  } else {
    coast_vertical_.predict(e1 - e0, direction_climb);
  }
  const double vertical = std::max(0.0, coast_vertical_.down_variance() - vertical_before);
  const double yaw_var = square(deg_to_rad(options_.gap_yaw_rate_stddev_dps)) * (e1 * e1 - e0 * e0);
  filter_.propagate_without_vo(displacement, Eigen::Vector3d(horizontal, horizontal, vertical), yaw_var);
  velocity_out_ = velocity;
  const double horizontal_step = displacement.head<2>().norm();
  if (over_seen_ground) {
    const double anchor = good_filter_.covariance()(PoseFilter::kDown, PoseFilter::kDown);
    filter_.set_down(coast_vertical_.down(), anchor + coast_vertical_.down_variance());
  } else {
    leave_seen_ground();  // nothing unless the last pose was over seen ground
  }
  if (over_seen_ground || follow_altimeter(utime, horizontal_step)) {
    // The mean climb of the coast: the per-frame one carries the range noise.
    velocity_out_.z() = (filter_.position().z() - good_filter_.position().z()) / e1;
  }
  last_frame_utime_ = utime;
  yaw_without_vo_ = true;  // as in a gap: the next INS yaw is taken as it is
  return update_attitude(utime);
}

Eigen::Vector3d YawFusionEstimator::coast_displacement(int64_t from, int64_t to, const Eigen::Vector3d& level_velocity,
                                                       Eigen::Vector3d* velocity_at_end) const {
  // The heading at t: the fused yaw at `from` plus the INS's turn since,
  // interpolated between the INS samples around t however far apart (a photo
  // flight's attitude comes with its photos); unchanged where there is none.
  constexpr int64_t kHeadingStepUs = 100000;
  const int64_t span = std::max<int64_t>(0, to - from);
  const int64_t bracket = std::max(static_cast<int64_t>(options_.max_ins_bracket_s * 1e6), span + kHeadingStepUs);
  auto ins_yaw_at = [&](int64_t t) {
    const auto a = ins_.at(options_.calibration.exposure_utime(t), bracket, AttitudePolicy::kInterpolate);
    return a ? std::optional<double>(a->yaw) : std::nullopt;
  };
  const auto start = ins_yaw_at(from);
  auto heading_at = [&](int64_t t) {
    const auto now = start ? ins_yaw_at(t) : std::nullopt;
    return filter_.yaw() + (now ? angle_difference(*now, *start) : 0.0);
  };
  const int64_t steps = std::max<int64_t>(1, (span + kHeadingStepUs - 1) / kHeadingStepUs);
  Eigen::Vector3d displacement = Eigen::Vector3d::Zero();
  for (int64_t k = 0; k < steps; ++k) {
    const int64_t a = from + span * k / steps, b = from + span * (k + 1) / steps;
    displacement += rotation_from_rpy(0.0, 0.0, heading_at(a + (b - a) / 2)) * level_velocity *
                    (static_cast<double>(b - a) * 1e-6);
  }
  *velocity_at_end = rotation_from_rpy(0.0, 0.0, heading_at(to)) * level_velocity;
  return displacement;
}

std::optional<SeenGround::Height> YawFusionEstimator::seen_ground_below(const Eigen::Vector3d& position, double yaw,
                                                                       const Eigen::Vector3d& beam,
                                                                       Eigen::Vector2d* spot, double* radius) const {
  const CoastOptions& c = options_.coast;
  // The ground where the beam hits it (a few metres from below the vehicle
  // when it is tilted: 5 m at 150 m and 2 deg), which the range measures.
  *spot = position.head<2>() + Eigen::Rotation2Dd(yaw) * beam.head<2>();
  constexpr double kMinRadiusM = 10.0;
  const double r = std::max(kMinRadiusM, c.seen_ground_radius_of_height * beam.z());
  if (radius != nullptr) *radius = r;
  return seen_ground_.ground_down(*spot, {r, c.seen_ground_min_points});
}

bool YawFusionEstimator::anchor_seen_ground() {
  // Each range says where the ground under its beam is (the vehicle's down
  // then + the levelled range); the points' fit there differs by what the
  // cloud's depths are off near it. That offset, averaged over the ranges of
  // the seen ground's window (one range's noise, 0.3 m at 200 m, would stay in
  // every down of the coast), is carried: the seen ground gives the ground's
  // shape relative to where the ranges put it.
  seen_ground_offset_ = 0.0;
  double sum = 0.0;
  int ranges = 0;
  for (const PlacedRange& r : recent_ranges_) {
    Eigen::Vector2d spot;
    const auto ground = seen_ground_below(r.position, r.yaw, r.beam, &spot);
    if (!ground) continue;
    sum += r.position.z() + r.beam.z() - ground->down;
    ++ranges;
  }
  if (ranges > 0) seen_ground_offset_ = sum / ranges;
  return ranges > 0;
}

std::vector<YawFusionEstimator::PlacedRange> YawFusionEstimator::place_ranges(int64_t prev_utime, int64_t utime,
                                                                              const Eigen::Vector3d& position,
                                                                              const Eigen::Vector3d& velocity) const {
  std::vector<PlacedRange> placed;
  const int64_t exposure = options_.calibration.exposure_utime(utime);
  // From the previous frame's exposure up to (not at) this one's: each range
  // once, and none whose arrival could be after the frame's delta.
  for (const RangeSample& sample : altimeter_.between(options_.calibration.exposure_utime(prev_utime), exposure)) {
    const auto attitude =
        ins_.at(sample.utime, static_cast<int64_t>(options_.max_ins_bracket_s * 1e6), options_.attitude_policy);
    if (!attitude) continue;
    const double before_s = static_cast<double>(exposure - sample.utime) * 1e-6;
    placed.push_back(PlacedRange{sample.utime, position - velocity * before_s, filter_.yaw(),
                                 level_range(sample.range_m, sample.beam_body, attitude->roll, attitude->pitch)});
  }
  return placed;
}

bool YawFusionEstimator::follow_seen_ground(int64_t utime, const Eigen::Vector3d& position,
                                            const Eigen::Vector3d& velocity, double e0,
                                            std::optional<double> direction_climb) {
  const int64_t start = options_.calibration.exposure_utime(last_good_utime_);
  const double e1 = static_cast<double>(utime - last_good_utime_) * 1e-6;
  const double speed = velocity.head<2>().norm();
  const double step = speed * (e1 - e0);
  double at = e0;  // the height filter's time (coast seconds)
  int ranges = 0, used = 0;
  for (const PlacedRange& r : place_ranges(last_frame_utime_, utime, position, velocity)) {
    ++ranges;
    const double t = static_cast<double>(r.utime - start) * 1e-6;
    coast_vertical_.predict(t - at, direction_climb);
    at = std::max(at, t);
    const double spacing = last_range_utime_ > 0 ? speed * static_cast<double>(r.utime - last_range_utime_) * 1e-6 : 0.0;
    last_range_utime_ = r.utime;
    Eigen::Vector2d spot;
    double radius = 0.0;
    const auto ground = seen_ground_below(r.position, r.yaw, r.beam, &spot, &radius);
    if (!ground) continue;
    const double seen = ground->down + seen_ground_offset_ - r.beam.z();
    // The beam on something the points do not show (a roof, a tree line): the
    // held climb (and the plane, which follows such a step) go on.
    if (std::abs(seen - coast_vertical_.down()) > coast_detector_.vertical_gate(step)) continue;
    // The range's variance, and the fit's counted once per radius flown:
    // spots less than a radius apart share most of their points, so their fit
    // errors do not average from range to range; counted at every range they
    // would make the filter trust a few radii of ground as many.
    const double shared = spacing > 0.0 ? std::max(1.0, radius / spacing) : 1.0;
    coast_vertical_.update(seen, square(options_.sensor_uncertainty.range_stddev(r.beam.z())) + ground->variance * shared);
    last_seen_ground_ = Eigen::Vector3d(spot.x(), spot.y(), ground->down + seen_ground_offset_);
    ++used;
  }
  coast_vertical_.predict(e1 - at, direction_climb);
  if (used > 0) {
    on_seen_ground_ = true;
    ++counters_.coast_seen_ground_poses;
    return true;
  }
  // No range since the last frame (the altimeter is slower than the camera): as the last one.
  return ranges == 0 && on_seen_ground_;
}

void YawFusionEstimator::leave_seen_ground() {
  if (!on_seen_ground_) return;
  on_seen_ground_ = false;
  if (coast_terrain_.anchored()) coast_terrain_.rebase(last_seen_ground_.head<2>(), last_seen_ground_.z());
}

bool YawFusionEstimator::follow_altimeter(int64_t utime, double horizontal_step_m) {
  const double height = altimeter_beam_at(utime).z();
  if (!std::isfinite(height) || !coast_terrain_.anchored()) return false;
  const Eigen::Vector2d horizontal = filter_.position().head<2>();
  double terrain = coast_terrain_.ground_down(horizontal) - height;
  const double previous = filter_.position().z();  // the last pose's down moved on by the held climb
  if (std::abs(terrain - previous) > coast_detector_.vertical_gate(horizontal_step_m)) {
    // As the coast detector judges a delta's dz against the altimeter: a jump
    // this large is the ground under the beam (a cliff, a building), not the vehicle.
    coast_terrain_.shift(previous - terrain);
    ++counters_.coast_ground_steps;
    terrain = previous;
  }
  // Two estimates of the same down from the last integrated frame on, with
  // independent errors: the held climb's (the coast model, which knows no
  // climb that starts or stops) and the terrain's (two ranges, and the
  // plane's slope off by terrain_slope_stddev per metre flown, which knows no
  // hill). Each weighted by the other's variance; the anchor's is common.
  const CoastOptions& c = options_.coast;
  const double held_variance = coast_vertical_.down_variance();
  const double slope_error = c.terrain_slope_stddev * coast_terrain_.distance(horizontal);
  const double terrain_variance =
      2.0 * square(options_.sensor_uncertainty.range_stddev(height)) + square(slope_error);
  const double sum = held_variance + terrain_variance;
  const double gain = sum > 0.0 ? held_variance / sum : 1.0;
  const double down = coast_vertical_.down() + gain * (terrain - coast_vertical_.down());
  const double anchor = good_filter_.covariance()(PoseFilter::kDown, PoseFilter::kDown);
  filter_.set_down(down, anchor + (sum > 0.0 ? held_variance * terrain_variance / sum : 0.0));
  return true;
}

double YawFusionEstimator::altimeter_height_at(int64_t utime) const { return altimeter_beam_at(utime).z(); }

Eigen::Vector3d YawFusionEstimator::altimeter_beam_at(int64_t utime) const {
  const auto attitude = ins_attitude_at(utime);
  const auto beam = altimeter_.beam_level(options_.calibration.exposure_utime(utime),
                                          static_cast<int64_t>(options_.max_altimeter_age_s * 1e6),
                                          attitude ? attitude->roll : roll_, attitude ? attitude->pitch : pitch_,
                                          options_.altimeter_interpolate);
  return beam ? *beam : Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
}

int32_t YawFusionEstimator::coast_bits(const vo_delta_t& delta) const {
  if (!options_.coast.enabled) return 0;
  int32_t bits = delta.quality & options_.coast.quality_mask;
  if (bits & vo_delta_t::QUALITY_STALE_ALTIMETER) {
    const auto attitude = ins_attitude_at(delta.utime);
    const auto fresh = altimeter_.height_agl(options_.calibration.exposure_utime(delta.utime),
                                             static_cast<int64_t>(options_.coast.max_range_age_s * 1e6),
                                             attitude ? attitude->roll : roll_, attitude ? attitude->pitch : pitch_,
                                             /*use_later=*/false);
    if (fresh) bits &= ~vo_delta_t::QUALITY_STALE_ALTIMETER;
  }
  return bits;
}

int32_t YawFusionEstimator::coast_reason(const vo_delta_t& delta, int32_t bits) {
  if (!options_.coast.enabled) return 0;
  const double height_change = altimeter_height_at(delta.utime) - last_altimeter_height_;
  const int32_t reason = coast_detector_.classify(delta, bits, height_change, coasting_);
  // A delta coasted for what the detector judged (not for a missing range or
  // features) could still be integrated, and coasting needs a held speed:
  // until speed_window_s of integrated motion is behind (the start, after a
  // gap) the speed is a few noisy deltas, whose levelling errors the next
  // deltas would have cancelled. Integrate it instead.
  if ((reason & kCoastQuality) == 0 && reason != 0 && !held_speed_ready()) return 0;
  return reason;
}

bool YawFusionEstimator::held_speed_ready() const {
  if (coasting_) return true;  // the speed is held already
  const int64_t window_us = static_cast<int64_t>(options_.coast.speed_window_s * 1e6);
  return coast_positions_.size() >= 2 && coast_positions_.back().utime - coast_positions_.front().utime >= window_us;
}

int32_t YawFusionEstimator::update_attitude(int64_t utime) {
  const auto attitude = ins_attitude_at(utime);
  if (!attitude) {
    ++counters_.ins_yaw_unusable;  // roll/pitch held from the last frame
    return 0;
  }
  roll_ = attitude->roll;
  pitch_ = attitude->pitch;
  if (attitude->yaw_variance < 0.0) {
    ++counters_.ins_yaw_unusable;
    return 0;
  }
  if (!yaw_from_ins_ || yaw_without_vo_) {
    if (yaw_without_vo_) ++counters_.yaw_from_ins_in_gap;
    filter_.reset_yaw(attitude->yaw, attitude->yaw_variance);
    yaw_from_ins_ = true;
    yaw_without_vo_ = false;
    ++counters_.ins_yaw_updates;
    return 0;
  }
  const auto result = filter_.update_yaw(attitude->yaw, attitude->yaw_variance, options_.ins_yaw_gate_sigma);
  if (result == PoseFilter::UpdateResult::kAccepted) {
    ++counters_.ins_yaw_updates;
    consecutive_yaw_rejections_ = 0;
    return 0;
  }
  ++counters_.ins_yaw_rejected;
  ++consecutive_yaw_rejections_;
  if (consecutive_yaw_rejections_ >= options_.max_consecutive_yaw_rejections) {
    // The INS has disagreed for too long to be an outlier: trust it again.
    std::ostringstream text;
    text << utime_label("INS", utime) << "yaw re-initialised after " << consecutive_yaw_rejections_
         << " rejections (innovation " << rad_to_deg(filter_.last_yaw_innovation()) << " deg)";
    note_problem(text.str());
    filter_.reset_yaw(attitude->yaw, attitude->yaw_variance);
    ++counters_.yaw_reinitialised;
    consecutive_yaw_rejections_ = 0;
  }
  return pose_t::FLAG_INS_YAW_REJECTED;
}

int32_t YawFusionEstimator::update_height(int64_t utime, double fallback_height) {
  const auto beam = altimeter_.beam_level(options_.calibration.exposure_utime(utime),
                                          static_cast<int64_t>(options_.max_altimeter_age_s * 1e6), roll_, pitch_,
                                          options_.altimeter_interpolate);
  const std::optional<double> height = beam ? std::optional<double>(beam->z()) : std::nullopt;
  if (beam) {
    const double c = std::cos(filter_.yaw()), s = std::sin(filter_.yaw());
    frame_ranges_.emplace_back(utime, Eigen::Vector3d(c * beam->x() - s * beam->y(), s * beam->x() + c * beam->y(),
                                                      beam->z()));
    while (frame_ranges_.size() > 512) frame_ranges_.pop_front();
  }
  const bool level_terrain = options_.altitude_mode == AltitudeMode::kLevelTerrain;
  const bool barometric = options_.altitude_mode == AltitudeMode::kBarometric;
  last_altimeter_height_ = height ? *height : std::numeric_limits<double>::quiet_NaN();
  if (!height) {
    ++counters_.frames_without_altimeter;
    if ((level_terrain || barometric) && filter_.terrain_initialised()) {
      height_agl_ = filter_.terrain_down() - filter_.position().z();
      have_height_ = true;
    } else if (std::isfinite(fallback_height)) {
      height_agl_ = fallback_height;
      have_height_ = true;
    }
    return pose_t::FLAG_NO_ALTIMETER;
  }
  height_agl_ = *height;
  have_height_ = true;
  if (level_terrain) {
    const double variance = square(options_.altimeter_stddev_m + options_.altimeter_stddev_fraction * *height);
    if (!filter_.terrain_initialised()) {
      filter_.anchor_terrain(*height, variance);
    } else if (filter_.update_height_agl(*height, variance, options_.altimeter_gate_sigma) ==
               PoseFilter::UpdateResult::kRejected) {
      // The ground under the beam stepped (slope, building, cliff): the level
      // terrain assumption broke here; keep the altitude, re-anchor the terrain.
      ++counters_.altimeter_rejected;
      filter_.anchor_terrain(*height, variance);
    }
  } else if (barometric) {
    update_barometric(utime, *height);
  }
  return 0;
}

void YawFusionEstimator::update_barometric(int64_t utime, double height) {
  // The datum (take-off) does not move and the barometer does not see the
  // ground, so unlike level_terrain nothing is ever re-anchored: a sample
  // that disagrees is either the barometer's outlier (not used) or, when
  // several in a row disagree, the VO-integrated down has drifted away
  // (reset to the barometer, which has not).
  const double variance = square(options_.altimeter_stddev_m + options_.altimeter_stddev_fraction * std::abs(height));
  if (!filter_.terrain_initialised()) {
    filter_.anchor_terrain(height, variance);
    consecutive_altimeter_rejections_ = 0;
    return;
  }
  // The datum is the first height, by definition of the height given: it
  // takes no correction, or it would absorb the dz errors the barometer is
  // there to remove.
  if (filter_.update_height_agl(height, variance, options_.altimeter_gate_sigma, /*terrain_moves=*/false) ==
      PoseFilter::UpdateResult::kAccepted) {
    consecutive_altimeter_rejections_ = 0;
    return;
  }
  ++counters_.altimeter_rejected;
  if (++consecutive_altimeter_rejections_ < options_.altimeter_max_consecutive_rejections) return;
  const double down = filter_.terrain_down() - height;
  std::ostringstream text;
  text << utime_label("ALTIMETER", utime) << "down reset to the barometric height after "
       << consecutive_altimeter_rejections_ << " rejections (" << filter_.position().z() << " -> " << down << " m)";
  note_problem(text.str());
  const double terrain_variance = filter_.covariance()(PoseFilter::kTerrain, PoseFilter::kTerrain);
  filter_.set_down(down, variance + terrain_variance);
  ++counters_.altimeter_down_resets;
  consecutive_altimeter_rejections_ = 0;
}

void YawFusionEstimator::add_map_fix(const map_fix_t& fix) {
  ++counters_.map_fixes_received;
  Eigen::Matrix2d r;
  r << fix.covariance_ne[0][0], fix.covariance_ne[0][1], fix.covariance_ne[1][0], fix.covariance_ne[1][1];
  const bool finite = std::isfinite(fix.position_ne[0]) && std::isfinite(fix.position_ne[1]) && r.allFinite();
  if (!options_.map_fix_enabled || !finite || !(r(0, 0) > 0.0) || !(r.determinant() > 0.0) ||
      std::abs(r(0, 1) - r(1, 0)) > 1e-9 * (r(0, 0) + r(1, 1))) {
    ++counters_.map_fixes_invalid;
    note_problem(utime_label("MAP_FIX", fix.utime) +
                 (options_.map_fix_enabled ? "non-finite, or a covariance not symmetric positive definite"
                                           : "map fixes are disabled (yaw_fusion.map_fix.enabled)"));
    return;
  }
  if (started_ && fix.utime + static_cast<int64_t>(options_.map_fix_apply_delay_s * 1e6) < last_frame_utime_) {
    ++counters_.map_fixes_late;
  }
  pending_fixes_.emplace(fix.utime, fix);
  while (pending_fixes_.size() > 64) {
    ++counters_.map_fixes_unmatched;
    pending_fixes_.erase(pending_fixes_.begin());
  }
}

int32_t YawFusionEstimator::apply_due_map_fixes(int64_t utime) {
  const int64_t delay = static_cast<int64_t>(options_.map_fix_apply_delay_s * 1e6);
  int32_t flags = 0;
  while (started_ && !pending_fixes_.empty() && pending_fixes_.begin()->first + delay <= utime) {
    const map_fix_t fix = pending_fixes_.begin()->second;
    pending_fixes_.erase(pending_fixes_.begin());
    flags |= apply_map_fix(fix);
  }
  return flags;
}

namespace {

// One measurement of the position at a frame, z = H truth + G b + v (v ~ R),
// b the map's systematic error (covariance B, never estimated; C the position
// error's covariance with it), applied to the axes in `moved` only.
struct FixUpdate {
  Eigen::MatrixXd h, g, r;
  Eigen::VectorXd z;
};

// The frame's position and covariance, the current one, and C, as one fix
// leaves them (valid for any gain: P - K M' - M K' + K S K').
struct FixState {
  Eigen::Vector3d frame_position;
  Eigen::Matrix3d frame_covariance, now, cross;
  Eigen::Vector3d correction = Eigen::Vector3d::Zero();
  // The last update applied: its innovation, S^-1 and cov(innovation, frame
  // position error) (k x 3), for states beside the position.
  Eigen::VectorXd innovation = Eigen::VectorXd();
  Eigen::MatrixXd s_inverse = Eigen::MatrixXd(), innovation_error = Eigen::MatrixXd();
};

// The Mahalanobis distance of the innovation; applies the update to `state`
// when it is within `gate`. `inflation` (>= 1) first scales the pose's own
// covariance of the axes moved at the frame (FixConsistency), which carries
// on to the current pose.
double apply_fix_update(const FixUpdate& u, const Eigen::Matrix3d& bias, const Eigen::Vector3d& moved, double gate,
                        double inflation, FixState* state) {
  if (inflation > 1.0) {
    const Eigen::Matrix3d added =
        (inflation - 1.0) * (moved.asDiagonal() * state->frame_covariance * moved.asDiagonal());
    state->frame_covariance += added;
    state->now += added;
  }
  const Eigen::VectorXd innovation = u.z - u.h * state->frame_position;
  // Position error e = estimate - truth: the innovation is -H e_f + G b + v,
  // so cov(e, innovation) = C G' - P_f H'.
  const Eigen::MatrixXd m = state->frame_covariance * u.h.transpose() - state->cross * u.g.transpose();
  Eigen::MatrixXd s = u.h * state->frame_covariance * u.h.transpose() - u.h * state->cross * u.g.transpose() -
                      u.g * state->cross.transpose() * u.h.transpose() + u.g * bias * u.g.transpose() + u.r;
  s = 0.5 * (s + s.transpose());
  const Eigen::MatrixXd s_inverse = s.inverse();
  const double distance = std::sqrt(std::max(0.0, innovation.dot(s_inverse * innovation)));
  if (!(distance <= gate)) return distance;
  state->innovation = innovation;
  state->s_inverse = s_inverse;
  state->innovation_error = -m.transpose();
  const Eigen::MatrixXd gain = moved.asDiagonal() * m * s_inverse;
  const Eigen::Vector3d correction = gain * innovation;
  const Eigen::Matrix3d loss = gain * m.transpose() + m * gain.transpose() - gain * s * gain.transpose();
  state->frame_position += correction;
  state->correction += correction;
  state->frame_covariance -= loss;
  state->now -= loss;
  state->cross = (Eigen::Matrix3d::Identity() - gain * u.h) * state->cross + gain * u.g * bias;
  return distance;
}

}  // namespace

int32_t YawFusionEstimator::apply_map_fix(const map_fix_t& fix) {
  auto at = std::find_if(published_.begin(), published_.end(),
                         [&](const PublishedPose& p) { return p.utime == fix.utime; });
  if (at == published_.end()) {
    ++counters_.map_fixes_unmatched;
    note_problem(utime_label("MAP_FIX", fix.utime) + "no pose of that frame (a gap, or older than kept), not used");
    return 0;
  }
  Eigen::Matrix2d r_horizontal;
  r_horizontal << fix.covariance_ne[0][0], fix.covariance_ne[0][1], fix.covariance_ne[1][0], fix.covariance_ne[1][1];
  const double horizontal = options_.map_fix_systematic_stddev_m, down = options_.map_fix_systematic_vertical_stddev_m;
  const Eigen::Matrix3d bias = Eigen::Vector3d(horizontal * horizontal, horizontal * horizontal, down * down).asDiagonal();
  // What the bias error, correlated with the map's error, moved the position by since the last fix.
  const Eigen::Vector2d bias_path = filter_.take_yaw_bias_path();
  map_error_cross_.topRows<2>() += bias_path * (bias_map_cross_.row(0) + bias_map_cross_.row(1));
  FixState state{at->position, at->covariance, filter_.reported_position_covariance(), map_error_cross_};

  // The horizontal: moves the horizontal only.
  FixUpdate h_update{Eigen::MatrixXd::Identity(2, 3), Eigen::MatrixXd::Identity(2, 3), r_horizontal,
                     Eigen::Vector2d(fix.position_ne[0], fix.position_ne[1])};
  const Eigen::Vector2d h_innovation = h_update.z - at->position.head<2>();
  const double distance = apply_fix_update(h_update, bias, Eigen::Vector3d(1.0, 1.0, 0.0),
                                           options_.map_fix_gate_sigma, horizontal_fix_consistency_.inflation(), &state);
  if (!(distance <= options_.map_fix_gate_sigma)) {
    ++counters_.map_fixes_rejected;
    char text[160];
    std::snprintf(text, sizeof(text), "innovation (%.2f, %.2f) m is %.1f sigma (map_fix.gate_sigma %.1f), rejected",
                  h_innovation.x(), h_innovation.y(), distance, options_.map_fix_gate_sigma);
    note_problem(utime_label("MAP_FIX", fix.utime) + text);
    return pose_t::FLAG_MAP_FIX_REJECTED;
  }
  horizontal_fix_consistency_.note(distance * distance);
  const std::optional<Eigen::Matrix2d> bias_cross =
      estimate_heading_bias(*at, state.innovation, state.s_inverse, state.innovation_error.leftCols<2>().transpose(),
                            bias, map_error_cross_);

  // The height, from the ground at the altimeter's spot less the levelled
  // range: moves the down only. The fix's horizontal error, and the map's,
  // move the ground read along its slope.
  const Eigen::Vector2d slope(fix.ground_gradient_ne[0], fix.ground_gradient_ne[1]);
  bool vertical = options_.map_fix_vertical && fix.ground_down_variance > 0.0 && at->range_ned.allFinite() &&
                  slope.allFinite() && std::isfinite(fix.ground_down_m);
  if (vertical) {
    const double height = at->range_ned.z();
    FixUpdate v_update{Eigen::MatrixXd::Zero(1, 3), Eigen::MatrixXd::Zero(1, 3), Eigen::MatrixXd(1, 1),
                       Eigen::VectorXd(1)};
    v_update.h(0, 2) = 1.0;
    v_update.g << slope.x(), slope.y(), 1.0;
    v_update.z(0) = fix.ground_down_m + slope.dot(at->range_ned.head<2>()) - height;
    const double range_scale = options_.sensor_uncertainty.range_scale_stddev * height;
    // The spot's place moves with the roll/pitch error by the height times it.
    const double spot = height * deg_to_rad(options_.sensor_uncertainty.roll_pitch_stddev_deg) * slope.norm();
    v_update.r(0, 0) = fix.ground_down_variance + slope.dot(r_horizontal * slope) +
                       square(options_.sensor_uncertainty.range_stddev(height)) + square(range_scale) + square(spot);
    const double v_innovation = v_update.z(0) - state.frame_position.z();
    const double v_distance =
        apply_fix_update(v_update, bias, Eigen::Vector3d(0.0, 0.0, 1.0), options_.map_fix_gate_sigma,
                         vertical_fix_consistency_.inflation(), &state);
    if (v_distance <= options_.map_fix_gate_sigma) {
      vertical_fix_consistency_.note(v_distance * v_distance);
    } else {
      vertical = false;
      ++counters_.map_fix_heights_rejected;
      char text[160];
      std::snprintf(text, sizeof(text), "height innovation %.2f m is %.1f sigma (map_fix.gate_sigma %.1f), not used",
                    v_innovation, v_distance, options_.map_fix_gate_sigma);
      note_problem(utime_label("MAP_FIX", fix.utime) + text);
    }
  }
  Eigen::Matrix3d after = 0.5 * (state.now + state.now.transpose());
  // The motion since the frame is independent of the error at it, so `after`
  // stays positive; guard against rounding.
  if (!(Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(after).eigenvalues().minCoeff() > 0.0)) {
    after = filter_.reported_position_covariance();
  }
  map_error_cross_ = state.cross;
  filter_.apply_position_fix(state.correction, after, vertical);
  if (bias_cross) filter_.hold_yaw_bias_correlation(*bias_cross);
  shift_placed_positions(state.correction, fix.utime);
  ++counters_.map_fixes_applied;
  if (vertical) ++counters_.map_fixes_with_height;
  return pose_t::FLAG_MAP_FIX_APPLIED;
}

std::optional<Eigen::Matrix2d> YawFusionEstimator::estimate_heading_bias(
    const PublishedPose& at, const Eigen::Vector2d& innovation, const Eigen::Matrix2d& s_inverse,
    const Eigen::Matrix2d& error_innovation, const Eigen::Matrix3d& map_bias, const Eigen::Matrix3d& frame_map_cross) {
  if (!options_.map_fix_estimates_heading_bias || !(filter_.yaw_bias_covariance().trace() > 0.0)) {
    return std::nullopt;
  }
  // The Gauss-Markov part decays: its covariances as at the frame, and with the map's error as at the last fix.
  auto decay_since = [&](int64_t utime) {
    return options_.ins_yaw_bias_correlation_s > 0.0
               ? std::exp(-static_cast<double>(last_frame_utime_ - utime) * 1e-6 / options_.ins_yaw_bias_correlation_s)
               : 1.0;
  };
  Eigen::Matrix2d frame_cross = at.yaw_bias_cross;
  frame_cross.col(1) *= decay_since(at.utime);
  bias_map_cross_.row(1) *= decay_since(bias_map_cross_utime_);
  bias_map_cross_utime_ = last_frame_utime_;
  // The bias error beta = b - estimate; the innovation is -e_f + (map error) + noise, so
  // cov(beta, innovation) = -cov(e_f, beta)' + cov(beta, map error).
  const Eigen::Matrix2d bias_innovation = -frame_cross.transpose() + bias_map_cross_.leftCols<2>();
  const Eigen::Matrix2d gain = bias_innovation * s_inverse;
  const Eigen::Matrix2d now_cross = filter_.yaw_bias_cross();
  filter_.correct_yaw_bias(gain * innovation, gain * bias_innovation.transpose());
  // cov(innovation, map error) = -cov(e_f, map error) + the map error's own.
  const Eigen::Matrix<double, 2, 3> innovation_map = -frame_map_cross.topRows<2>() + map_bias.topRows<2>();
  bias_map_cross_ -= gain * innovation_map;
  // cov(e+, beta+) = cov(e, beta) - cov(e, innovation) S^-1 cov(beta, innovation)'.
  return Eigen::Matrix2d(now_cross - error_innovation * s_inverse * bias_innovation.transpose());
}

void YawFusionEstimator::shift_placed_positions(const Eigen::Vector3d& shift, int64_t from_utime) {
  for (PublishedPose& p : published_) {
    if (p.utime >= from_utime) p.position += shift;
  }
  for (auto& p : recent_positions_) p.second += shift;
  for (CoastSample& s : coast_positions_) s.position += shift;
  for (PlacedRange& r : recent_ranges_) r.position += shift;
  coast_terrain_.move_with_position(shift);
  seen_ground_.move_with_position(shift);
  last_seen_ground_ += shift;
}

void YawFusionEstimator::remember_poses(const std::vector<pose_t>& poses, size_t from) {
  for (size_t i = from; i < poses.size(); ++i) {
    const pose_t& p = poses[i];
    PublishedPose entry;
    entry.utime = p.utime;
    entry.position = {p.position_ned[0], p.position_ned[1], p.position_ned[2]};
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) entry.covariance(r, c) = p.position_covariance[r][c];
    entry.range_ned = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
    entry.yaw_bias_cross = filter_.yaw_bias_cross();
    for (auto it = frame_ranges_.rbegin(); it != frame_ranges_.rend(); ++it) {
      if (it->first == p.utime) {
        entry.range_ned = it->second;
        break;
      }
    }
    published_.push_back(entry);
  }
  const int64_t keep = static_cast<int64_t>((options_.map_fix_apply_delay_s + 10.0) * 1e6);
  while (!published_.empty() && published_.back().utime - published_.front().utime > keep) published_.pop_front();
}

pose_t YawFusionEstimator::make_pose(int64_t utime, int32_t flags) const {
  pose_t pose{};
  pose.utime = utime;
  const Eigen::Vector3d p = filter_.position();
  const Eigen::Matrix3d pc = filter_.reported_position_covariance();
  for (int i = 0; i < 3; ++i) {
    pose.position_ned[i] = p(i);
    pose.velocity_ned[i] = velocity_out_(i);
    for (int j = 0; j < 3; ++j) pose.position_covariance[i][j] = pc(i, j);
  }
  pose.roll = roll_;
  pose.pitch = pitch_;
  pose.yaw = filter_.fused_yaw();
  // No POSE field is ever non-finite (a consumer's arithmetic would spread
  // it): an unknown height is -1 and flagged.
  pose.height_agl_m = have_height_ ? height_agl_ : -1.0;
  if (!have_height_) flags |= pose_t::FLAG_NO_ALTIMETER;
  pose.yaw_variance = filter_.reported_yaw_variance();
  pose.flags = flags | (yaw_from_ins_ ? 0 : pose_t::FLAG_INITIALIZING);
  pose.horizontal_protection_level_m =
      horizontal_protection_level(pc.topLeftCorner<2, 2>(), pose.flags, options_.protection_level);
  pose.frames = frames_;
  return pose;
}

}  // namespace nadir
