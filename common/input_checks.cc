#include "common/input_checks.h"

#include <algorithm>
#include <cmath>

#include "common/geometry.h"

namespace nadir {
namespace {

bool finite_all(const double* values, int n) {
  for (int i = 0; i < n; ++i) {
    if (!std::isfinite(values[i])) return false;
  }
  return true;
}

std::string verdict_reason(StreamClock::Verdict verdict) {
  switch (verdict) {
    case StreamClock::Verdict::kAhead:
      return "time_ahead";
    case StreamClock::Verdict::kBehind:
      return "time_behind";
    case StreamClock::Verdict::kDuplicate:
      return "time_duplicate";
    case StreamClock::Verdict::kAccepted:
      break;
  }
  return "accepted";
}

}  // namespace

const OptionsSchema<InputCheckOptions>& InputCheckOptions::schema() {
  using O = InputCheckOptions;
  static const OptionsSchema<O> schema = [] {
    OptionsSchema<O> s("input_checks", "Plausibility checks every estimator applies to its inputs "
                                       "(common/input_checks.h).");
    s.above("max_ahead_s", 0.0, 3600.0, "s", "newer than the newest accepted time by more: rejected",
            &O::max_ahead_s)
        .above("max_behind_s", 0.0, 3600.0, "s", "older than its channel's newest by more: rejected",
               &O::max_behind_s)
        .number("relock_messages", 2, 1000, "", "this many rejected messages agreeing with each other re-anchor",
                &O::relock_messages)
        .above("max_attitude_step_rate_rad_s", 0.0, 1000.0, "rad/s", "INS attitude change between samples per second",
               &O::max_attitude_step_rate_rad_s)
        .number("attitude_step_noise_sigmas", 0.0, 20.0, "", "... plus this many sigmas of the samples' own noise",
                &O::attitude_step_noise_sigmas)
        .above("max_angular_rate_rad_s", 0.0, 1000.0, "rad/s", "INS angular rates", &O::max_angular_rate_rad_s)
        .number("min_range_m", 0.0, 1e5, "m", "a valid altimeter range below this: rejected", &O::min_range_m)
        .above("max_range_m", 0.0, 1e5, "m", "... or above this", &O::max_range_m)
        .above("max_abs_normalized", 0.0, 100.0, "", "undistorted track coordinates |x|, |y|",
               &O::max_abs_normalized)
        .number("pixel_margin", 0.0, 10000.0, "px", "track pixels this far outside the image: rejected",
                &O::pixel_margin)
        .above("max_speed_m_s", 0.0, 10000.0, "m/s", "VO_DELTA translation over its interval, plus ...",
               &O::max_speed_m_s)
        .number("levelling_allowance_deg", 0.0, 45.0, "deg", "... altitude x tan(this)", &O::levelling_allowance_deg)
        .above("max_yaw_rate_rad_s", 0.0, 1000.0, "rad/s", "VO_DELTA dyaw over its interval", &O::max_yaw_rate_rad_s)
        .rule("min_range_m", [](const O& o) { return o.min_range_m < o.max_range_m; }, "must be < max_range_m");
    return s;
  }();
  return schema;
}

InputCheckOptions InputCheckOptions::from_config(const Config& root) {
  return schema().read(root.section_or_empty("input_checks"));
}

void InputCheckOptions::Check() const { schema().check(*this); }

StreamClock::Verdict StreamClock::admit(int64_t utime, const InputCheckOptions& options, int64_t* gate_newest) {
  const int64_t ahead_us = static_cast<int64_t>(options.max_ahead_s * 1e6);
  const int64_t behind_us = static_cast<int64_t>(options.max_behind_s * 1e6);
  const int64_t reference = gate_newest != nullptr ? std::max(*gate_newest, newest_) : newest_;
  Verdict verdict = Verdict::kAccepted;
  if (started_ && utime == newest_) {
    verdict = Verdict::kDuplicate;
  } else if ((started_ || gate_newest != nullptr) && utime > reference + ahead_us) {
    verdict = Verdict::kAhead;
  } else if (started_ && utime < newest_ - behind_us) {
    verdict = Verdict::kBehind;
  }
  bool relocked = false;
  if (verdict == Verdict::kAhead || verdict == Verdict::kBehind) {
    // A run of rejected messages that agree with each other is the stream
    // itself having moved: re-anchor on it.
    const bool continues_run = run_length_ > 0 && utime > run_newest_ && utime <= run_newest_ + ahead_us;
    run_length_ = continues_run ? run_length_ + 1 : 1;
    run_newest_ = utime;
    if (run_length_ < options.relock_messages) return verdict;
    relocked = true;
    verdict = Verdict::kAccepted;
  }
  if (verdict != Verdict::kAccepted) return verdict;
  newest_ = started_ && !relocked ? std::max(newest_, utime) : utime;
  started_ = true;
  run_length_ = 0;
  if (gate_newest != nullptr) *gate_newest = relocked ? utime : std::max(*gate_newest, utime);
  return verdict;
}

bool InputGate::reject(const std::string& channel, int64_t utime, const std::string& reason,
                       const std::string& detail) {
  ++counts_[channel + "." + reason];
  ++rejected_total_;
  last_rejection_ = channel + " utime " + std::to_string(utime) + ": " + detail + ", rejected";
  return false;
}

bool InputGate::admit_time(const std::string& channel, int64_t utime) {
  if (!have_newest_) newest_ = utime;
  have_newest_ = true;
  const StreamClock::Verdict verdict = clocks_[channel].admit(utime, options_, &newest_);
  if (verdict == StreamClock::Verdict::kAccepted) return true;
  ++time_rejected_;
  return reject(channel, utime, verdict_reason(verdict),
                verdict == StreamClock::Verdict::kDuplicate ? "same sensor time as the previous message"
                                                            : "sensor time inconsistent with the stream's");
}

namespace {
// The white noise the INS reports for one axis of one sample (0 without
// stddev), at most 0.1 rad: a larger figure says the attitude is not usable.
double reported_noise(const ins_t& msg, int axis) {
  if (!msg.has_stddev || !std::isfinite(msg.attitude_stddev[axis])) return 0.0;
  return std::clamp(msg.attitude_stddev[axis], 0.0, 0.1);
}
}  // namespace

bool InputGate::attitude_step_plausible(const ins_t& before, const ins_t& after) const {
  const double dt = std::abs(static_cast<double>(after.utime - before.utime)) * 1e-6;
  // Within a short interval the attitude cannot jump; across a long one (a
  // gap, a restart) anything is possible.
  if (dt >= 1.0) return true;
  const double steps[3] = {after.roll - before.roll, after.pitch - before.pitch,
                           angle_difference(after.yaw, before.yaw)};
  for (int axis = 0; axis < 3; ++axis) {
    // Two samples' own noise (as the INS reports it) may add to the motion.
    const double noise = std::hypot(reported_noise(before, axis), reported_noise(after, axis));
    const double limit = options_.max_attitude_step_rate_rad_s * std::max(dt, 0.01) +
                         options_.attitude_step_noise_sigmas * noise;
    if (std::abs(steps[axis]) > limit) return false;
  }
  return true;
}

bool InputGate::admit(const std::string& channel, const ins_t& msg) {
  const double attitude[3] = {msg.roll, msg.pitch, msg.yaw};
  bool ok = finite_all(attitude, 3) && std::abs(msg.roll) <= M_PI && std::abs(msg.pitch) <= M_PI / 2 &&
            std::abs(msg.yaw) <= 4 * M_PI;
  if (!ok) return reject(channel, msg.utime, "attitude", "attitude not finite or out of range");
  if (msg.has_rates) {
    ok = finite_all(msg.angular_rate, 3);
    for (int i = 0; ok && i < 3; ++i) ok = std::abs(msg.angular_rate[i]) <= options_.max_angular_rate_rad_s;
    if (!ok) return reject(channel, msg.utime, "rates", "angular rate not finite or above max_angular_rate_rad_s");
  }
  if (msg.has_stddev && !finite_all(msg.attitude_stddev, 3)) {
    return reject(channel, msg.utime, "stddev", "attitude stddev not finite");
  }
  if (have_ins_ && !attitude_step_plausible(last_ins_, msg)) {
    // The samples rejected in a row agree with each other: the accepted one
    // before them was the odd one out.
    const bool continues_run = step_run_length_ > 0 && attitude_step_plausible(step_run_last_, msg);
    step_run_length_ = continues_run ? step_run_length_ + 1 : 1;
    step_run_last_ = msg;
    if (step_run_length_ < options_.relock_messages) {
      return reject(channel, msg.utime, "attitude_step", "attitude step inconsistent with the previous sample");
    }
  }
  step_run_length_ = 0;
  // The driver says this sample's time is not to be trusted (its clock
  // estimate is restarting): an attitude at the wrong time is worse than none.
  if (msg.flags & ins_t::FLAG_TIME_JUMP) {
    return reject(channel, msg.utime, "time_untrusted", "flagged FLAG_TIME_JUMP by its driver");
  }
  if (!admit_time(channel, msg.utime)) return false;
  have_ins_ = true;
  last_ins_ = msg;
  return true;
}

bool InputGate::admit(const std::string& channel, const altimeter_t& msg) {
  if (!finite_all(msg.beam_body, 3)) return reject(channel, msg.utime, "beam", "beam direction not finite");
  const double norm = std::sqrt(msg.beam_body[0] * msg.beam_body[0] + msg.beam_body[1] * msg.beam_body[1] +
                                msg.beam_body[2] * msg.beam_body[2]);
  if (std::abs(norm - 1.0) > 0.01) return reject(channel, msg.utime, "beam", "beam direction not a unit vector");
  if (msg.validity == altimeter_t::VALID_OK &&
      !(std::isfinite(msg.range_m) && msg.range_m >= options_.min_range_m && msg.range_m <= options_.max_range_m)) {
    return reject(channel, msg.utime, "range", "valid range not finite or outside [min_range_m, max_range_m]");
  }
  return admit_time(channel, msg.utime);
}

bool InputGate::admit(const std::string& channel, const tracks_t& msg) {
  if (msg.prev_utime != 0 && msg.prev_utime >= msg.utime) {
    return reject(channel, msg.utime, "prev_utime", "prev_utime not before utime");
  }
  const double margin = options_.pixel_margin;
  for (int32_t i = 0; i < msg.num_tracks; ++i) {
    const double norms[4] = {msg.prev_norm[i][0], msg.prev_norm[i][1], msg.curr_norm[i][0], msg.curr_norm[i][1]};
    const double pixels[4] = {msg.prev_px[i][0], msg.prev_px[i][1], msg.curr_px[i][0], msg.curr_px[i][1]};
    bool ok = finite_all(norms, 4) && finite_all(pixels, 4);
    for (int k = 0; ok && k < 4; ++k) ok = std::abs(norms[k]) <= options_.max_abs_normalized;
    for (int k = 0; ok && k < 4; ++k) {
      const double extent = (k % 2 == 0) ? msg.width : msg.height;
      ok = pixels[k] >= -margin && pixels[k] <= extent + margin;
    }
    if (!ok) {
      return reject(channel, msg.utime, "coordinates",
                    "track " + std::to_string(i) + " not finite or outside the image / field of view");
    }
  }
  return admit_time(channel, msg.utime);
}

bool InputGate::admit(const std::string& channel, const image_t& msg) {
  return admit_time(channel, msg.utime);
}

bool InputGate::admit(const std::string& channel, const vo_delta_t& msg) {
  const double values[6] = {msg.dx, msg.dy, msg.dz, msg.dyaw, msg.ground_roll, msg.ground_pitch};
  if (!finite_all(values, 6) || !finite_all(&msg.covariance[0][0], 36)) {
    return reject(channel, msg.utime, "non_finite", "motion or covariance not finite");
  }
  if (msg.prev_utime != 0) {
    const double dt = static_cast<double>(msg.utime - msg.prev_utime) * 1e-6;
    if (!(dt > 0.0)) return reject(channel, msg.utime, "prev_utime", "prev_utime not before utime");
    const double distance = std::sqrt(msg.dx * msg.dx + msg.dy * msg.dy + msg.dz * msg.dz);
    // The levelling allowance grows with the height (at most the altimeter's
    // plausible range), not with the interval.
    const double height = std::isfinite(msg.altitude_m) ? std::clamp(msg.altitude_m, 0.0, options_.max_range_m) : 0.0;
    const double allowance = height * std::tan(options_.levelling_allowance_deg * M_PI / 180.0);
    if (distance > options_.max_speed_m_s * dt + allowance ||
        std::abs(msg.dyaw) > options_.max_yaw_rate_rad_s * dt) {
      return reject(channel, msg.utime, "motion", "motion faster than max_speed_m_s (+ levelling allowance) / max_yaw_rate_rad_s");
    }
  }
  return admit_time(channel, msg.utime);
}

bool InputGate::admit(const std::string& channel, const ground_points_t& msg) {
  const size_t n = static_cast<size_t>(std::max(0, msg.num_points));
  if (msg.num_points < 0 || msg.track_id.size() != n || msg.position_m.size() != n || msg.depth_sigma_m.size() != n) {
    return reject(channel, msg.utime, "size", "num_points does not match its arrays");
  }
  for (size_t i = 0; i < n; ++i) {
    const float* p = msg.position_m[i].data();
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]) ||
        !(msg.depth_sigma_m[i] >= 0.0f) || !std::isfinite(msg.depth_sigma_m[i])) {
      return reject(channel, msg.utime, "non_finite",
                    "point " + std::to_string(i) + ": position not finite or depth sigma not a finite value >= 0");
    }
  }
  return admit_time(channel, msg.utime);
}

void InputGate::add_counters(StatusReport* report) const {
  report->counters.emplace_back("rejected_inputs", static_cast<double>(rejected_total_));
  for (const auto& [key, count] : counts_) report->counters.emplace_back("rejected." + key, static_cast<double>(count));
}

void InputGate::warn_if_rejecting(StatusReport* report) const {
  if (rejected_total_ == rejected_at_last_warn_) return;
  const int64_t recent = rejected_total_ - rejected_at_last_warn_;
  rejected_at_last_warn_ = rejected_total_;
  if (report->state == status_t::STATE_OK) report->state = status_t::STATE_WARN;
  report->detail = std::to_string(recent) + " input message(s) rejected since the last status" +
                   (time_rejected_ > 0 ? " (times inconsistent with their stream: a second publisher?)" : "") +
                   "; last: " + last_rejection_;
}

}  // namespace nadir
