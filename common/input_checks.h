#pragma once
// Plausibility checks at every estimator input, one place per message type
// (shared by every process that reads it). A message that decodes but carries
// impossible values -- a misconfigured driver, a second publisher on the same
// channel, an INS during alignment, a failing altimeter -- is rejected,
// counted per channel and reason, and never reaches the estimator's state.
//
// Time: a message more than max_ahead_s ahead of the newest sensor time this
// gate accepted on any of its channels (the INS, at 100 Hz, sets the pace where
// it is an input), more than max_behind_s behind its own channel's newest
// time, or with the same time as that, is rejected; it never becomes the
// reference, so one future-stamped message cannot lock the real stream out.
// The stream itself may move (a driver restart): a run of `relock_messages`
// rejected messages that agree with each other (increasing, each within
// max_ahead_s of the one before) re-anchors the channel. An INS sample that
// its driver flags FLAG_TIME_JUMP (its clock estimate restarting, see the INS
// bridge) is rejected: an attitude at the wrong time is worse than none.
// The decision depends only on the messages of that channel in their order,
// so a lockstep replay decides exactly as the live run did.

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "common/config.h"
#include "common/options_schema.h"
#include "common/status.h"
#include "nadir/altimeter_t.hpp"
#include "nadir/ground_points_t.hpp"
#include "nadir/image_t.hpp"
#include "nadir/ins_t.hpp"
#include "nadir/tracks_t.hpp"
#include "nadir/vo_delta_t.hpp"

namespace nadir {

struct InputCheckOptions {
  double max_ahead_s = 1.0;               // newer than the channel's newest accepted time by more: rejected
  double max_behind_s = 1.0;              // older than it by more: rejected
  int relock_messages = 5;                // agreeing rejected messages that re-anchor a channel
  double max_attitude_step_rate_rad_s = 6.0;  // attitude change between accepted INS samples per second ...
  double attitude_step_noise_sigmas = 6.0;    // ... plus this many sigmas of the two samples' reported white noise
  double max_angular_rate_rad_s = 10.0;   // INS angular rates
  double min_range_m = 0.05;              // a valid altimeter range outside [min, max]: rejected
  double max_range_m = 5000.0;
  double max_abs_normalized = 4.0;        // undistorted track coordinates |x|, |y| (76 deg off axis)
  double pixel_margin = 64.0;             // track pixels this far outside the image: rejected
  double max_speed_m_s = 250.0;           // VO_DELTA translation over its interval ...
  // ... plus altitude_m * tan(this): the levelling error of the two frames
  // (INS roll/pitch error, eps_prev - eps_curr) moves a step by h * that
  // difference, and the next step takes it back; so the gate must let it
  // through, or the steps no longer telescope (white 3 deg roll/pitch noise
  // gives a 4.2 deg sigma difference, 22 m at 300 m in 70 ms).
  double levelling_allowance_deg = 25.0;
  double max_yaw_rate_rad_s = 6.0;        // VO_DELTA dyaw over its interval

  // Section `input_checks` of the config root; absent keys keep the defaults.
  static InputCheckOptions from_config(const Config& root);
  // Throws ConfigError naming the key and the allowed range.
  void Check() const;
  static const OptionsSchema<InputCheckOptions>& schema();  // every key of `input_checks:`
};

// The newest accepted sensor time of one channel and the run of rejected
// messages that may re-anchor it.
class StreamClock {
 public:
  enum class Verdict { kAccepted, kAhead, kBehind, kDuplicate };
  // `gate_newest`: the newest time accepted on any channel of the gate (it is
  // raised to this message's time when accepted); nullptr: this channel only.
  Verdict admit(int64_t utime, const InputCheckOptions& options, int64_t* gate_newest);

 private:
  bool started_ = false;
  int64_t newest_ = 0;
  int run_length_ = 0;        // rejected messages that agree with each other so far
  int64_t run_newest_ = 0;
};

class InputGate {
 public:
  explicit InputGate(const InputCheckOptions& options) : options_(options) {}

  // Each returns true when the message may go on to the estimator.
  bool admit(const std::string& channel, const ins_t& msg);
  bool admit(const std::string& channel, const altimeter_t& msg);
  bool admit(const std::string& channel, const tracks_t& msg);
  bool admit(const std::string& channel, const image_t& msg);
  bool admit(const std::string& channel, const vo_delta_t& msg);
  bool admit(const std::string& channel, const ground_points_t& msg);

  const InputCheckOptions& options() const { return options_; }
  int64_t rejected() const { return rejected_total_; }
  // Rejections on channels whose messages disagree with the stream's time:
  // the sign of a second publisher (or a driver's clock gone wrong).
  int64_t time_rejected() const { return time_rejected_; }
  // "INS utime 123: roll 1e+09 rad not finite or out of range"; empty if none.
  const std::string& last_rejection() const { return last_rejection_; }
  // Appends "rejected.<CHANNEL>.<reason>" counters (only reasons that occurred).
  void add_counters(StatusReport* report) const;
  // Sets the report WARN when messages were rejected since the last call.
  void warn_if_rejecting(StatusReport* report) const;

 private:
  bool attitude_step_plausible(const ins_t& before, const ins_t& after) const;
  bool admit_time(const std::string& channel, int64_t utime);
  bool reject(const std::string& channel, int64_t utime, const std::string& reason, const std::string& detail);

  InputCheckOptions options_;
  std::map<std::string, StreamClock> clocks_;
  bool have_newest_ = false;
  int64_t newest_ = 0;  // newest time accepted on any channel
  std::map<std::string, int64_t> counts_;  // "<CHANNEL>.<reason>"
  bool have_ins_ = false;
  ins_t last_ins_{};
  int step_run_length_ = 0;  // INS samples rejected in a row for their attitude step
  ins_t step_run_last_{};
  int64_t rejected_total_ = 0;
  int64_t time_rejected_ = 0;
  mutable int64_t rejected_at_last_warn_ = 0;
  std::string last_rejection_;
};

}  // namespace nadir
