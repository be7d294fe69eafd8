#pragma once
// An altimeter range sampled before its frame (altimeter_mode latest: up to
// one altimeter period old) was measured from where the aircraft was then.
// Seen from the camera at the frame's time, the spot the beam hit is
//   spot = range * beam_level - age * velocity_level,
// so the frame's range and beam become |spot| and spot's direction. Every
// solver then puts the ground through the spot the beam really hit: without
// it a climb, a descent or a slope under the beam biases each pair's scale by
// range rate x age / range (README, Rough ground).

#include <Eigen/Core>

#include <cstdint>

namespace nadir::vo {

// Smoothed camera velocity in the level frame of the last solved frame
// (m/s): each solved pair's translation over its time, folded in with a
// time constant (the per-pair translation carries the INS attitude noise of
// both frames, which a window averages away), carried into each new frame
// by its heading change. Cleared by a frame that was not solved.
class LevelVelocity {
 public:
  explicit LevelVelocity(double time_constant_s) : time_constant_s_(time_constant_s) {}
  void reset() { utime_ = kNone; }
  // A solved pair prev_utime -> utime: translation in prev's level frame
  // (metres), heading change dyaw (rad).
  void add(int64_t prev_utime, int64_t utime, const Eigen::Vector3d& translation, double dyaw);
  // The velocity at frame `utime` (level frame), if the last solved pair ended there.
  bool at(int64_t utime, Eigen::Vector3d* velocity) const;

 private:
  static constexpr int64_t kNone = INT64_MIN;
  double time_constant_s_;
  Eigen::Vector3d velocity_ = Eigen::Vector3d::Zero();
  int64_t utime_ = kNone;
};

// Moves (range_m, beam_body) from where the range was sampled, age_s before
// the frame (<= 0: nothing to move) at attitude `sampled` (roll, pitch), to
// the camera at the frame, at attitude `frame`: the beam is then given in the
// body at the frame's attitude. velocity_level: in the frame's level frame.
struct RollPitch {
  double roll = 0, pitch = 0;
};
void move_range_to_frame(double age_s, const Eigen::Vector3d& velocity_level, const RollPitch& sampled,
                         const RollPitch& frame, double* range_m, Eigen::Vector3d* beam_body);

}  // namespace nadir::vo
