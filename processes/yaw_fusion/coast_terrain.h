#pragma once
// The ground under the vehicle while coasting. Without VO nothing measures a
// climb, but the altimeter still measures the height above the ground, and the
// last integrated frames tell where that ground was: each one's down position
// plus its levelled height is a ground point, and the solver's ground patch
// (VO_DELTA ground_roll / ground_pitch, in the level frame of the frame) gives
// the slope. While coasting the ground is that plane -- the mean ground point
// of the last window of integrated frames, carried to the last one along the
// mean slope -- and the vehicle is the levelled height above it.
//
// No bus, no filter: the estimator feeds it the integrated frames and asks for
// the ground down coordinate below a horizontal position.

#include <Eigen/Core>

#include <cstdint>
#include <deque>

namespace nadir {

// The slope of a ground patch tilted by (ground_roll, ground_pitch) (normal
// Ry(pitch) Rx(roll) e_z in the level frame x forward, y right, z down: see
// vo_solver/plane_model.h) as the change of the ground's down coordinate per
// metre north and east, for a frame whose level x axis points to `yaw`.
Eigen::Vector2d ground_gradient_ned(double ground_roll, double ground_pitch, double yaw);

class CoastTerrain {
 public:
  explicit CoastTerrain(double window_s) : window_us_(static_cast<int64_t>(window_s * 1e6)) {}

  // An integrated frame at `utime`: its position (NED), its levelled
  // altimeter height (NaN: none, no ground point) and the ground gradient of
  // its delta (ground_gradient_ned; non-finite: not used).
  void note_frame(int64_t utime, const Eigen::Vector3d& position, double height_agl, const Eigen::Vector2d& gradient);
  // Forgets the frames and the plane (a VO gap: the position was dead-reckoned
  // away from them; the next coast needs new ones).
  void clear() {
    frames_.clear();
    anchored_ = false;
  }

  // Fixes the plane from the frames of the window (call when a coast starts).
  // False when none of them had a ground point: then there is no plane.
  bool anchor();
  bool anchored() const { return anchored_; }
  void release() { anchored_ = false; }
  // The ground under the beam stepped (a cliff, a building) by this much
  // (down): the plane moves with it.
  void shift(double down_m) { origin_down_ += down_m; }
  // The vehicle's position was corrected by `shift` (a map fix): the frames
  // and the plane were placed with it and move with it.
  void move_with_position(const Eigen::Vector3d& shift) {
    for (Frame& f : frames_) f.position += shift;
    origin_ += shift.head<2>();
    origin_down_ += shift.z();
  }
  // The ground at `horizontal` is known to be at `ground_down` (seen by a
  // frame): the plane goes through it with its slope, its distance from there.
  void rebase(const Eigen::Vector2d& horizontal, double ground_down) {
    origin_ = horizontal;
    origin_down_ = ground_down;
  }
  // The down coordinate of the anchored ground below (north, east).
  double ground_down(const Eigen::Vector2d& horizontal) const;
  // Horizontal distance (m) from the anchor.
  double distance(const Eigen::Vector2d& horizontal) const { return (horizontal - origin_).norm(); }
  // The slope of the anchored plane (d down / d north, d down / d east).
  const Eigen::Vector2d& gradient() const { return gradient_; }

 private:
  struct Frame {
    int64_t utime;
    Eigen::Vector3d position;
    double height_agl;
    Eigen::Vector2d gradient;
  };
  int64_t window_us_;
  std::deque<Frame> frames_;
  bool anchored_ = false;
  Eigen::Vector2d origin_ = Eigen::Vector2d::Zero();    // horizontal position of the anchor
  double origin_down_ = 0.0;                              // ground down coordinate there
  Eigen::Vector2d gradient_ = Eigen::Vector2d::Zero();
};

}  // namespace nadir
