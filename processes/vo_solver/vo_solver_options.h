#pragma once
// Options of the vo_solver process, read from the `vo_solver:` section (and
// the shared `camera:` / `altimeter:` sections) of the config.

#include <Eigen/Core>

#include "common/config.h"
#include "common/options_schema.h"
#include "processes/vo_solver/delta_uncertainty.h"
#include "processes/vo_solver/frame_sync.h"
#include "processes/vo_solver/heading_check.h"
#include "processes/vo_solver/translation_solver.h"

namespace nadir {

struct VoSolverOptions {
  vo::SolverOptions solver;
  vo::SyncOptions sync;
  vo::HeadingCheckOptions heading;      // QUALITY_HEADING_CONTRADICTS
  vo::UncertaintyOptions uncertainty;  // `vo_solver.uncertainty:`: INS/altimeter errors in VO_DELTA's covariance
  Eigen::Matrix3d body_from_camera = Eigen::Matrix3d::Identity();
  Eigen::Vector3d default_beam_body = Eigen::Vector3d::UnitZ();

  // Reads and checks; throws ConfigError naming the file and dotted key.
  static VoSolverOptions from_config(const Config& root);
  // Every key of `vo_solver:` (options_schema.h); camera and altimeter are
  // read by their own readers.
  static const OptionsSchema<VoSolverOptions>& schema();
};

}  // namespace nadir
