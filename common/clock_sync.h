#pragma once
// Maps a device clock onto the vehicle time base from (device time, arrival
// time) pairs. Arrival = device + offset + drift * t + delay, with delay >= 0
// and jittered, so the lower envelope of (arrival - device) tracks the clock
// offset: the minimum per block of samples, fitted by a line over a sliding
// window (offset and drift). The constant minimum transport delay cannot be
// observed; `min_delay_us` from config is subtracted for it.
//
// Every sample is checked against the model as it arrives (not per block):
// - earlier than the model allows by more than the threshold, or device time
//   going backwards: the estimate restarts at once;
// - later than the late bound: a delayed read or an upward offset step, which
//   one sample cannot tell apart, so the sample is not trusted; late samples
//   for step_confirm_s in a row are a step and restart the estimate.
// The late bound is learned from the link: the lower median over the window
// of each block's arrival spread (its largest minus its smallest arrival -
// device time), times 1.25, and never below the threshold. A link whose
// reads jitter by as much as the threshold (serial bytes arriving 0-20 ms
// late) would otherwise see every sample in the jitter's top fraction of a
// millisecond flagged, because the fitted floor sits that much off; an
// offset step adds to every sample at once and so exceeds the bound from the
// first sample after it. The median ignores a block that a step or a rare
// held-up read widened.
// After a restart (also one asked for with restart(), e.g. a device reopen)
// samples are not trusted until the running minimum has held (not dropped by
// more than half the threshold) for settle_s of device time: a backlog read
// at once after a reopen lowers the minimum sample by sample until it is
// drained, and would otherwise be stamped late by the backlog's age.

#include <cstdint>
#include <deque>
#include <string>

#include "common/options_schema.h"

namespace nadir {

struct ClockSyncOptions {
  double window_s = 30.0;            // sliding window for the fit
  double block_s = 1.0;              // one minimum per block
  double jump_threshold_us = 20000;  // error beyond which a sample's time is not trusted
  double min_delay_us = 0.0;         // known minimum transport delay
  double settle_s = 0.2;             // after a restart: the minimum must hold this long
  double step_confirm_s = 0.5;       // late beyond the threshold this long: an offset step
  void Check() const;                // throws ConfigError naming the option
  // The keys above from a `clock_sync:` section; absent keys keep `defaults`.
  static ClockSyncOptions from_config(const Config& section, const ClockSyncOptions& defaults);
  static const OptionsSchema<ClockSyncOptions>& schema();
};

struct ClockSyncState {
  bool valid = false;
  bool settling = false;     // restarted, minimum not yet held for settle_s
  double offset_us = 0.0;    // vehicle - device at the newest sample
  double drift_ppm = 0.0;
  int blocks = 0;
  int64_t samples = 0;
  int64_t jumps = 0;         // restarts of the estimate
  int64_t late = 0;          // samples later than the model by more than late_bound_us
  double late_bound_us = 0;  // the bound in force (>= jump_threshold_us), see above
  int64_t untrusted = 0;     // samples add() returned false for
  std::string last_jump;     // why the last restart happened
};

class ClockSync {
 public:
  explicit ClockSync(const ClockSyncOptions& options);

  // Adds one pair. Returns true when the sample's vehicle time (to_vehicle
  // right after this call) is trusted to within the jump threshold; false when
  // it restarted the estimate, arrived while the estimate settles, or arrived
  // later than the model allows.
  bool add(int64_t device_us, int64_t arrival_us);
  // Drops the estimate (the device was reopened: it may be another device or
  // a rebooted one). No-op when there is no estimate yet.
  void restart(const std::string& why);
  bool valid() const { return state_.valid; }
  // Vehicle time of a device time; requires valid().
  int64_t to_vehicle(int64_t device_us) const;
  const ClockSyncState& state() const { return state_; }

 private:
  struct Block {
    int64_t device_us;   // device time of the block's minimum
    double offset_us;    // minimum (arrival - device) in the block
    int64_t start_us;    // device time the block began
    double max_offset_us;  // maximum (arrival - device) in the block
  };
  double predict(int64_t device_us) const;
  // Checks a sample against the current model; may restart. False: not trusted.
  bool check_against_model(int64_t device_us, double offset);
  void add_to_blocks(int64_t device_us, double offset);
  // While settling: false until the minimum held for settle_s.
  bool settled(int64_t device_us, double offset);
  void refit();
  // The late bound from the closed blocks' arrival spreads.
  void update_late_bound();

  ClockSyncOptions options_;
  std::deque<Block> blocks_;
  // Arrival spreads of the latest closed blocks (at most a window's worth):
  // a property of the link, so kept across restarts of the clock estimate.
  std::deque<double> spreads_us_;
  bool have_current_ = false;
  Block current_{};
  int64_t last_device_us_ = 0;
  bool late_run_ = false;         // consecutive late samples ...
  int64_t late_run_start_us_ = 0;  // ... since this device time
  double settle_offset_us_ = 0.0;  // minimum the settle clock runs from ...
  int64_t settle_start_us_ = 0;    // ... since this device time
  bool settle_anchored_ = false;
  // Fit: offset(t) = intercept_ + slope_ * (t - reference_us_)
  int64_t reference_us_ = 0;
  double intercept_ = 0.0;
  double slope_ = 0.0;
  ClockSyncState state_;
};

}  // namespace nadir
