#pragma once
// The height while coasting: the down coordinate and the climb rate as a
// two-state Kalman filter. It starts at the last integrated frame's down
// with the climb held from the frames before (its error sigma_v); the climb
// changes as a random walk q (the aircraft's own vertical accelerations), so
// with no measurement the down's variance grows as the coast model's,
// sigma_v^2 t^2 + q^2 t^3 / 3 (coast_position_variance). Over ground the
// last frames saw, each down measured there (that ground minus the levelled
// range) updates both: the height follows it, the climb is measured over it
// and is what carries on past it.
//
// No bus, no options: the estimator gives the model's numbers and the
// measurements' variances.

#include <Eigen/Core>

namespace nadir {

class CoastVertical {
 public:
  // From `down` (m, exact: the anchor frame's variance is the estimator's),
  // climbing at `climb_mps` (down per second) known to `climb_stddev_mps`.
  void start(double down, double climb_mps, double climb_stddev_mps);
  // `dt_s` on: the down moves by `rate_mps` x dt (the held climb, or the one
  // a stale-range delta's direction gives), the covariance grows by the
  // constant-climb model with a climb random walk of `q` (m/s per sqrt(s)).
  void predict(double dt_s, double rate_mps, double q);
  // A down measured with `variance` (m^2). Returns the innovation (measured
  // minus predicted) before the update.
  double update(double measured_down, double variance);

  // The state (down, climb) and its covariance, as a model of
  // CoastVerticalModes mixes them.
  const Eigen::Vector2d& state() const { return state_; }
  const Eigen::Matrix2d& covariance() const { return covariance_; }
  void set(const Eigen::Vector2d& state, const Eigen::Matrix2d& covariance) {
    state_ = state;
    covariance_ = covariance;
  }

  double down() const { return state_(0); }
  double climb() const { return state_(1); }  // m/s, down positive
  double down_variance() const { return covariance_(0, 0); }
  double climb_variance() const { return covariance_(1, 1); }

 private:
  Eigen::Vector2d state_ = Eigen::Vector2d::Zero();        // down (m), climb (m/s, down positive)
  Eigen::Matrix2d covariance_ = Eigen::Matrix2d::Zero();
};

}  // namespace nadir
