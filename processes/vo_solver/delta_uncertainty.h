#pragma once
// What the image residual does not see: the uncertainty of VO_DELTA's
// (dx, dy, dz, dyaw) from the INS attitude and the altimeter range that every
// solve takes as exact. The solver's covariance, sigma^2 (J^T W J)^-1, is the
// image noise only; a levelling error of the INS shifts the whole ground
// footprint by ~h * epsilon and a range error scales the whole motion, and
// neither leaves a residual.
//
// Propagated to first order: central finite differences of a cheap model of
// the solve (delta_model below) with respect to the two frames' roll and
// pitch, the two ranges and a common range scale factor, times the sensor
// variances of `vo_solver.uncertainty:`. The model: a level ground plane at
// the height the altimeter gives, nine rays of a grid over the image, the
// prev rays levelled with prev's attitude and intersected with the plane, the
// curr rays levelled with curr's attitude and fitted to those points by a 2-D
// similarity (translation, heading, height). It is not the solver: it only has
// to move as the solver moves when an attitude or a range is wrong, which the
// unit tests check against Monte Carlo runs of the real solver.

#include <Eigen/Core>

#include "common/config.h"
#include "common/delta_uncertainty_options.h"
#include "processes/vo_solver/translation_solver.h"

namespace nadir::vo {

// The options and the per-frame levelling variances live in common/ (yaw
// fusion takes the same levelling part out again).
using UncertaintyOptions = DeltaUncertaintyOptions;
using nadir::frame_levelling_variances;
using nadir::levelling_variance_m2;
using nadir::levelling_yaw_variance_rad2;

// The sensor inputs of delta_model, in this order.
enum SensorInput : int {
  kPrevRoll = 0,
  kPrevPitch,
  kCurrRoll,
  kCurrPitch,
  kPrevRange,
  kCurrRange,
  kRangeScale,  // relative: both ranges times (1 + s)
  kSensorInputs
};
using SensorVector = Eigen::Matrix<double, kSensorInputs, 1>;
using SensorJacobian = Eigen::Matrix<double, 4, kSensorInputs>;

// The pair's sensor inputs as measured (range scale 0).
SensorVector measured_inputs(const FramePair& pair);

// The cheap model of the solve for the scene that `est` describes (motion
// est.translation / est.dyaw, level ground est.altitude_m below prev), seen
// with the sensor inputs `inputs`: (dx, dy, dz, dyaw). With symmetric_dz the
// dz is the mean of the forward and the time-reversed fit, as the solver does.
Eigen::Vector4d delta_model(const FramePair& pair, const Estimate& est, bool symmetric_dz,
                            const SensorVector& inputs);

// d (dx, dy, dz, dyaw) / d inputs at the measured inputs (central differences).
SensorJacobian sensor_jacobian(const FramePair& pair, const Estimate& est, bool symmetric_dz);

// Diagonal covariance of the sensor inputs of this pair.
Eigen::Matrix<double, kSensorInputs, kSensorInputs> sensor_input_covariance(const FramePair& pair,
                                                                             const UncertaintyOptions& options);

// J Sigma J^T over (dx, dy, dz, dyaw), plus the INS heading difference's
// variance on dyaw for the `flow` variant, plus the model error terms. Zero
// when the estimate carries no motion (failed solve) or the model is not
// finite there.
Eigen::Matrix4d sensor_covariance(const FramePair& pair, const Estimate& est, const SolverOptions& solver,
                                  const UncertaintyOptions& options);

// The model error of one delta with horizontal translation `step` (level
// frame): the walks' variance per metre times its length, along and across
// it. The walks are the variant's: feature_depth_walk_* for feature_depth,
// relief_walk_* for the one-plane variants. `relief_along_m2_per_m` is added
// to the along-step variance per metre (feature_depth's relief part,
// relief_along_variance_per_m).
Eigen::Matrix2d relief_walk_covariance(const Eigen::Vector2d& step, Variant variant,
                                       const UncertaintyOptions& options, double relief_along_m2_per_m = 0.0);

// feature_depth: the along-step variance per metre that the relief under the
// altimeter's spot adds (feature_depth_relief_heights x the anchor's model
// variance x the height); 0 for the other variants.
double relief_along_variance_per_m(const Estimate& est, Variant variant, const UncertaintyOptions& options);

// The hook of vo_solver_node: adds sensor_covariance to est->covariance.
void add_sensor_uncertainty(const FramePair& pair, const SolverOptions& solver, const UncertaintyOptions& options,
                            Estimate* est);

}  // namespace nadir::vo
