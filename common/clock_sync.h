#pragma once
// Maps a device clock onto the vehicle time base from (device time, arrival
// time) pairs. Arrival = device + offset + drift * t + delay, with delay >= 0
// and jittered, so the lower envelope of (arrival - device) tracks the clock
// offset: the minimum per block of samples, fitted by a line over a sliding
// window (offset and drift). The constant minimum transport delay cannot be
// observed; `min_delay_us` from config is subtracted for it.
// Jumps (device time stepping, a sample impossibly early, the envelope moving
// by more than the threshold) restart the estimate and are counted.

#include <cstdint>
#include <deque>
#include <string>

namespace nadir {

struct ClockSyncOptions {
  double window_s = 30.0;          // sliding window for the fit
  double block_s = 1.0;            // one minimum per block
  double jump_threshold_us = 20000;  // envelope step that counts as a jump
  double min_delay_us = 0.0;       // known minimum transport delay
  void Check() const;              // throws ConfigError naming the option
};

struct ClockSyncState {
  bool valid = false;
  double offset_us = 0.0;   // vehicle - device at the newest sample
  double drift_ppm = 0.0;
  int blocks = 0;
  int64_t samples = 0;
  int64_t jumps = 0;
  int64_t rejected = 0;
  std::string last_jump;     // why the last restart happened
};

class ClockSync {
 public:
  explicit ClockSync(const ClockSyncOptions& options);

  // Adds one pair. Returns false when the pair started a new estimate (a jump).
  bool add(int64_t device_us, int64_t arrival_us);
  bool valid() const { return state_.valid; }
  // Vehicle time of a device time; requires valid().
  int64_t to_vehicle(int64_t device_us) const;
  const ClockSyncState& state() const { return state_; }

 private:
  struct Block {
    int64_t device_us;   // device time of the block's minimum
    double offset_us;    // minimum (arrival - device) in the block
    int64_t start_us;    // device time the block began
  };
  double predict(int64_t device_us) const;
  void refit();
  void restart(const std::string& why);

  ClockSyncOptions options_;
  std::deque<Block> blocks_;
  bool have_current_ = false;
  Block current_{};
  int64_t last_device_us_ = 0;
  // Fit: offset(t) = intercept_ + slope_ * (t - reference_us_)
  int64_t reference_us_ = 0;
  double intercept_ = 0.0;
  double slope_ = 0.0;
  ClockSyncState state_;
};

}  // namespace nadir
