#pragma once
// Synchronises INS attitude and altimeter range to frame times by sensor time
// only (DESIGN.md "Runtime"). Each frame time gets one attitude and one range,
// computed once and cached, so a frame has the same attitude in both pairs it
// belongs to (that is what makes roll/pitch errors telescope, paper eq. 21-23).
// Bounded buffers; independent of the bus.
//
// Attitude policies: `interpolate` waits for the INS sample after the frame
// and slerps between the two around it; `propagate` takes the newest sample
// at or before the frame and rotates it on to the frame time with the body
// rates (the sample's own, or from the two newest samples), so a frame never
// waits for the future. Either way the attitude is a function of the samples'
// times and values only, never of when they arrived: live = lockstep replay.

#include <Eigen/Core>

#include <cstdint>
#include <map>
#include <string>

#include "common/attitude_propagation.h"
#include "common/sensor_calibration.h"
#include "nadir/altimeter_t.hpp"
#include "nadir/ins_t.hpp"

namespace nadir::vo {

struct SyncOptions {
  AttitudePolicy attitude_policy = AttitudePolicy::kAuto;
  // propagate: INS samples are never closer together than this, so a frame
  // less than this after the newest sample has all its samples (no wait). A
  // closer pair, once seen, lowers the bound (counted as ins_interval_short).
  int64_t ins_min_interval_us = 9000;
  int64_t max_ins_gap_us = 100000;           // bracketing INS samples farther apart (or propagated
                                             // farther than this): no attitude
  int64_t max_ins_extrapolation_us = 20000;  // one-sided INS sample at most this far: used as is
  int64_t altimeter_staleness_us = 200000;   // nearest valid range farther than this: stale
  int64_t altimeter_wait_us = 300000;        // INS time to wait for an altimeter sample after a frame
  int64_t settle_us = 0;                     // extra sensor time to wait when a channel can reorder itself
  // false ("latest"): use only altimeter samples at or before the frame and
  // never wait for a later one -- the frame is solved as soon as the INS
  // sample after it is there (lowest latency). true ("interpolate"): wait up
  // to altimeter_wait_us for the sample after the frame and interpolate.
  bool altimeter_interpolate = false;
  int64_t max_frame_interval_us = 250000;    // prev -> curr longer than this: frame gap
  int max_pending_frames = 64;               // TRACKS waiting for INS; the oldest is flushed flagged
  int max_ins_samples = 3000;                // buffer sizes (oldest by utime dropped first)
  int max_altimeter_samples = 2000;
  int max_cached_frames = 256;
  // Camera time offset (attitude and range are looked up at the exposure
  // time, stamp + offset) and altimeter scale/bias (ranges corrected as they
  // are added). Frames are still named by their stamp.
  SensorCalibration calibration;
  // Throws std::invalid_argument naming the field and the allowed range
  // (ConfigError naming the config key for the calibration).
  void Check() const;
};

struct FrameState {
  bool has_attitude = false;
  double roll = 0, pitch = 0, yaw = 0;
  // The share of one INS sample's white attitude noise variance in roll,
  // pitch and yaw (attitude_propagation.h: 1/2 for two samples averaged).
  double attitude_noise_share = 1.0;
  bool has_range = false;   // a valid range was found (maybe stale)
  bool range_stale = false;
  double range_m = 0;
  // The range's sample time before the frame's exposure (0: interpolated to
  // it, or a sample at it; negative: a sample after it) and the attitude
  // then (the frame's where the INS does not cover it). A range sampled
  // before the frame was measured from where the aircraft was then
  // (range_at_frame.h).
  int64_t range_age_us = 0;
  double range_roll = 0, range_pitch = 0;
  Eigen::Vector3d beam_body = Eigen::Vector3d::UnitZ();
};

class FrameSync {
 public:
  FrameSync(const SyncOptions& options, const Eigen::Vector3d& default_beam_body);

  void add_ins(const ins_t& ins);
  void add_altimeter(const altimeter_t& altimeter);

  // True once the inputs for a frame at `utime` are final: an INS sample at
  // or after utime + settle exists (propagate, settle 0: or the newest sample
  // is less than the INS interval before utime, so no other sample at or
  // before it can come), and an altimeter sample at or after it exists or the
  // INS has run altimeter_wait_us further. Messages of one channel are assumed
  // to arrive in utime order unless settle_us covers their reordering; across
  // channels any interleaving is fine.
  // `utime` is the frame's stamp; the sensors are read at its exposure time
  // (stamp + options.calibration's camera time offset).
  bool ready(int64_t utime) const;

  // The frame's attitude and range at its exposure time, computed on first
  // use and then cached by the stamp.
  const FrameState& frame_state(int64_t utime);

  size_t ins_samples() const { return ins_.size(); }
  size_t altimeter_samples() const { return altimeter_.size(); }
  int64_t invalid_altimeter_samples() const { return invalid_altimeter_; }
  int64_t dropped_samples() const { return dropped_samples_; }
  // INS intervals shorter than ins_min_interval_us (propagate waits longer after one).
  int64_t short_ins_intervals() const { return ins_complete_.short_intervals(); }

 private:
  struct Range {
    bool valid;
    double range_m;
    Eigen::Vector3d beam_body;
  };
  FrameState compute(int64_t stamp_utime) const;
  bool ins_final(int64_t utime) const;
  void attitude_at(int64_t utime, FrameState* state) const;
  void interpolate_attitude(int64_t utime, FrameState* state) const;
  void propagate_attitude_to(int64_t utime, FrameState* state) const;
  void range_at(int64_t utime, FrameState* state) const;

  SyncOptions options_;
  Eigen::Vector3d default_beam_body_;
  std::map<int64_t, InsAttitude> ins_;
  std::map<int64_t, Range> altimeter_;
  std::map<int64_t, FrameState> cache_;
  int64_t invalid_altimeter_ = 0;
  int64_t dropped_samples_ = 0;
  InsCompleteness ins_complete_;
};

}  // namespace nadir::vo
