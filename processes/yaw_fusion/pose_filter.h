#pragma once
// The estimator state of yaw fusion, independent of any bus: local NED
// position (origin = first frame), yaw, and (level_terrain mode only) the down
// coordinate of the terrain under the vehicle, the current frame's levelling
// heading error and the VO heading drift rate, with a full covariance.
//
// Prediction uses one VO delta: the translation (dx, dy) measured in the level
// frame of the previous frame is registered in the world with the yaw held for
// that previous frame, Rz(psi_{k-1}) * (dx, dy); the yaw then advances by the
// VO dyaw. Each frame thus has exactly one yaw, used for the delta that starts
// at it -- the same one-attitude-per-frame rule that makes the roll/pitch
// errors telescope in the paper's eq. (21)-(23).
//
// The INS yaw update corrects the yaw and the heading drift rate only (a
// "consider" gain for the rest): translations already registered stay where
// they were, but the covariance is updated with the Joseph form for the gain
// actually used, so the reported position covariance (including yaw/position
// cross terms) stays honest.

#include <Eigen/Core>

#include <cstdint>

#include "common/geometry.h"

namespace nadir {

class PoseFilter {
 public:
  // kYawLevelling: the current frame's levelling heading error (a consider
  // state, estimate 0; step_frame_yaw_levelling). kHeadingDrift: the rate
  // (rad/s) at which the VO heading chain drifts (apply_heading_drift),
  // estimated by the INS yaw updates.
  static constexpr int kNorth = 0, kEast = 1, kDown = 2, kYaw = 3, kTerrain = 4, kYawLevelling = 5,
                       kHeadingDrift = 6, kSize = 7;
  using Vector = Eigen::Matrix<double, kSize, 1>;
  using Matrix = Eigen::Matrix<double, kSize, kSize>;

  enum class UpdateResult { kAccepted, kRejected };

  // Position at the origin (exactly known), yaw with its variance.
  void initialise(double yaw, double yaw_variance);
  // Position and yaw as a previous run left them (a restart from a
  // checkpoint), with their uncertainty; no correlation between the two.
  void restore(const Eigen::Vector3d& position, const Eigen::Matrix3d& position_covariance, double yaw,
               double yaw_variance);
  bool initialised() const { return initialised_; }

  // Integrates one VO delta. `translation` = (dx, dy, dz) in the level frame
  // of the previous frame, `covariance` over (dx, dy, dz, dyaw). Returns the
  // world (NED) translation that was added.
  Eigen::Vector3d predict_with_delta(const Eigen::Vector3d& translation, double dyaw,
                                     const Eigen::Matrix4d& covariance);

  // The heading error a frame's levelling puts into the VO chain
  // (levelling_yaw_variance_rad2): a delta's dyaw carries curr's term
  // minus prev's, so over consecutive deltas it telescopes and the chain's
  // yaw holds only the current frame's (and the first frame's). Call after
  // predict_with_delta, whose covariance must not contain these, with the
  // delta's two frames (any ids, e.g. sensor times) and their variances: the
  // yaw error loses prev's term and takes curr's, kept as kYawLevelling so
  // that INS yaw updates see its correlation. A delta that does not start at
  // the frame held (the first one, or after a gap) starts from an
  // independent term of its prev frame.
  void step_frame_yaw_levelling(int64_t prev_frame, int64_t curr_frame, double prev_variance, double curr_variance);

  // The VO heading chain drifts at a rate that changes slowly with the
  // ground (a first-order Gauss-Markov process: `stddev` rad/s, correlation
  // time `time_s`; DeltaUncertaintyOptions::heading_drift_stddev_rad_s). Call
  // after each integrated delta, `dt` its duration: the yaw takes the drift
  // estimate out of the delta's dyaw, and the drift decays towards 0 with its
  // variance growing back towards stddev^2. The INS yaw updates estimate the
  // drift through its correlation with the yaw. stddev 0: no drift state.
  void apply_heading_drift(double dt, double stddev, double time_s);

  // Moves the position by a world displacement without VO (gaps) and adds
  // independent variance to the position axes and the yaw.
  void propagate_without_vo(const Eigen::Vector3d& displacement_ned, const Eigen::Vector3d& position_variance_added,
                            double yaw_variance_added);

  // Replaces the down position by a value known independently of the
  // state (coasting: the terrain model minus the altimeter height), with its
  // variance, dropping its correlation with the other states.
  void set_down(double down, double variance);

  // An absolute horizontal fix (a map match) applied as the estimator
  // computed it (yaw_fusion_estimator.h): the position moves by `correction`
  // (north, east) and its reported horizontal covariance becomes `covariance`.
  // What the shared errors had put into the horizontal position up to now is
  // in that covariance: they restart from here (the origin frame's levelling,
  // the horizontal displacement the range scale multiplies, the position
  // part of the yaw bias). The horizontal position's correlation with the
  // other states is dropped, as in set_down.
  void apply_horizontal_fix(const Eigen::Vector2d& correction, const Eigen::Matrix2d& covariance);
  // A fix of the whole position (north, east, down): as apply_horizontal_fix
  // for the horizontal, and with `vertical` the down as well (the range
  // scale's share of the vertical restarts, the terrain state moves with it:
  // the altimeter's height over it is unchanged). Without `vertical`,
  // apply_horizontal_fix: the down is left as it is.
  void apply_position_fix(const Eigen::Vector3d& correction, const Eigen::Matrix3d& covariance, bool vertical);

  // Yaw measurement (rad) with its variance. Rejected when the squared
  // innovation exceeds gate_sigma^2 times its variance.
  UpdateResult update_yaw(double measured_yaw, double variance, double gate_sigma);
  // Replaces the yaw by a measurement, dropping its correlation with position.
  void reset_yaw(double yaw, double variance);
  // Innovation of the last update_yaw call (rad), for diagnostics.
  double last_yaw_innovation() const { return last_yaw_innovation_; }

  // Level-terrain altitude correction. The terrain state is the down
  // coordinate of the ground under the vehicle; a height above ground h
  // measures terrain - down.
  bool terrain_initialised() const { return terrain_initialised_; }
  void anchor_terrain(double height_agl, double variance);
  // `terrain_moves` false: the terrain state is a fixed datum (a barometer's
  // take-off point), only down takes the correction.
  UpdateResult update_height_agl(double height_agl, double variance, double gate_sigma, bool terrain_moves = true);
  double terrain_down() const { return x_(kTerrain); }

  // Errors shared between deltas, kept beside the state (README § Consistency).
  // Each VO delta's levelling error is h_{k-1} eps_{k-1} - h_k eps_k: summed
  // over the deltas it telescopes to the origin frame's and the current
  // frame's terms, so the filter integrates each delta without its levelling
  // part and the reported covariance adds those two frames' variances once.
  // An altimeter scale error s moves the position by s times the displacement
  // since the origin. The INS yaw bias b (a random walk) is in the fused yaw,
  // which the INS updates pull onto the INS heading, and every translation is
  // registered with that yaw: it moves the position by b times the
  // translation turned by 90 deg, summed over the deltas with the bias each
  // had (a consider state (e_north, e_east, b_walk, b_markov) kept beside the
  // filter: b = b_walk + b_markov, the walk's part never decays, the
  // Gauss-Markov part by `yaw_bias.markov_decay` per delta).
  // `prev/curr_levelling_variance`: m^2 per horizontal axis (height^2 sigma^2).
  struct YawBiasStep {
    double walk_variance_added = 0.0;    // rad^2
    double markov_decay = 1.0;           // exp(-dt / tau)
    double markov_variance_added = 0.0;  // rad^2
  };
  void add_shared_errors(double prev_levelling_variance, double curr_levelling_variance,
                         const Eigen::Vector3d& world_translation, double range_scale_variance,
                         const YawBiasStep& yaw_bias);
  // False until the heading bias's prior is in: the first add_shared_errors
  // after initialise / restore, or restore_yaw_bias.
  bool yaw_bias_started() const { return yaw_bias_started_; }
  // Position covariance and yaw variance with the shared errors.
  Eigen::Matrix3d reported_position_covariance() const;
  // The reported yaw is the yaw state (fused_yaw): what the fixes estimate
  // is the heading the steps need, which holds the camera's mounting as
  // well as the INS bias, so the yaw's variance keeps the bias's own.
  double reported_yaw_variance() const {
    const Eigen::Matrix2d& bias =
        yaw_bias_corrected_ ? yaw_bias_unestimated_ : Eigen::Matrix2d(yaw_bias_.block<2, 2>(kWalkBias, kWalkBias));
    return p_(kYaw, kYaw) + bias(0, 0) + bias(1, 1) + 2.0 * bias(0, 1);
  }

  // The INS heading bias (its walk and Gauss-Markov parts, rad) as absolute
  // fixes estimate it (correct_yaw_bias; 0 without fixes). The yaw state
  // follows the INS heading, bias and all; yaw() is the heading with the
  // estimate taken out, and every translation is registered with it. The
  // shared errors' bias terms are then those of the bias less its estimate.
  // cov(position error, bias error), rows north/east, columns walk/markov:
  Eigen::Matrix2d yaw_bias_cross() const { return yaw_bias_.block<2, 2>(0, kWalkBias); }
  Eigen::Matrix2d yaw_bias_covariance() const { return yaw_bias_.block<2, 2>(kWalkBias, kWalkBias); }
  double yaw_bias_estimate() const { return yaw_bias_estimate_.sum(); }
  // The sum of the translations turned by 90 deg since the last call: what a
  // bias error moved the position by since then, per radian.
  Eigen::Vector2d take_yaw_bias_path() {
    const Eigen::Vector2d path = yaw_bias_path_;
    yaw_bias_path_.setZero();
    return path;
  }
  // Moves the estimate by `correction` (walk, markov) and takes `variance_removed` from its covariance.
  void correct_yaw_bias(const Eigen::Vector2d& correction, const Eigen::Matrix2d& variance_removed);
  // After a horizontal fix (apply_position_fix), which leaves the position
  // uncorrelated with everything: the horizontal position error's
  // covariance with the bias error is `cross` (as yaw_bias_cross()). The
  // reported covariance stays what the fix set; the part of it the bias
  // explains moves into the shared errors, so later fixes see the drift the
  // bias makes over the whole path, not only since the last fix.
  void hold_yaw_bias_correlation(const Eigen::Matrix2d& cross);

  // The heading bias part of the filter, as a checkpoint keeps it.
  struct YawBiasState {
    Eigen::Vector2d estimate = Eigen::Vector2d::Zero();          // (walk, markov), rad
    Eigen::Matrix2d covariance = Eigen::Matrix2d::Zero();        // of the estimate's error
    bool estimated = false;                                      // a fix has moved the estimate
    Eigen::Matrix2d prior_covariance = Eigen::Matrix2d::Zero();  // the bias's, as if none had (when estimated)
  };
  YawBiasState yaw_bias_state() const;
  // After restore(): the heading bias as a previous run left it, its error
  // uncorrelated with the position (whose restored covariance holds what the
  // bias did to it); the prior is not added again.
  void restore_yaw_bias(const YawBiasState& state);

  Eigen::Vector3d position() const { return x_.head<3>(); }
  // The heading the steps are registered with.
  double yaw() const { return yaw_bias_estimate_.isZero(0.0) ? x_(kYaw) : wrap_angle(x_(kYaw) - yaw_bias_estimate()); }
  // The yaw state: the INS heading fused with the VO's turns, its bias in it.
  double fused_yaw() const { return x_(kYaw); }
  double yaw_variance() const { return p_(kYaw, kYaw); }
  Eigen::Matrix3d position_covariance() const { return p_.topLeftCorner<3, 3>(); }
  const Matrix& covariance() const { return p_; }

 private:
  // A fix of the first N position axes: moves them by `correction`, restarts
  // the shared errors' share of the position, and sets the filter's block so
  // that the reported covariance of those axes is `covariance` (their
  // correlation with the other states dropped).
  template <int N>
  void fix_position(const Eigen::Matrix<double, N, 1>& correction, const Eigen::Matrix<double, N, N>& covariance);
  // Joseph-form covariance update for gain k on measurement row h with variance r.
  void joseph_update(const Vector& k, const Eigen::Matrix<double, 1, kSize>& h, double r);

  bool initialised_ = false;
  bool terrain_initialised_ = false;
  Vector x_ = Vector::Zero();
  Matrix p_ = Matrix::Zero();
  double last_yaw_innovation_ = 0.0;
  bool have_heading_drift_ = false;
  bool have_yaw_levelling_frame_ = false;
  int64_t yaw_levelling_frame_ = 0;
  // Shared errors (add_shared_errors).
  bool have_origin_levelling_ = false;
  double origin_levelling_variance_ = 0.0, frame_levelling_variance_ = 0.0;
  Eigen::Vector3d displacement_ = Eigen::Vector3d::Zero();  // integrated VO, world
  double range_scale_variance_ = 0.0;
  // Covariance of (north, east) position error from the yaw bias and the
  // bias's two parts.
  static constexpr int kWalkBias = 2, kMarkovBias = 3;
  Eigen::Matrix4d yaw_bias_ = Eigen::Matrix4d::Zero();
  Eigen::Vector2d yaw_bias_estimate_ = Eigen::Vector2d::Zero();  // (walk, markov), rad
  // The bias's covariance as if no fix had estimated it (reported_yaw_variance), once one has.
  bool yaw_bias_corrected_ = false;
  bool yaw_bias_started_ = false;
  Eigen::Vector2d yaw_bias_path_ = Eigen::Vector2d::Zero();
  Eigen::Matrix2d yaw_bias_unestimated_ = Eigen::Matrix2d::Zero();
};

}  // namespace nadir
