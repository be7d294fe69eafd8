#pragma once
// The solver measures the camera's motion; VO_DELTA reports the motion of the
// INS reference point (the point the ground truth, the INS and POSE refer
// to). With the camera `lever` (camera centre from the INS reference, body
// frame) the two differ by the lever arm turned from prev's attitude to
// curr's: camera = INS + R lever in prev's level frame, so
//   translation_INS = translation_camera - (R_curr - R_prev) lever,
// R_prev = R(roll_prev, pitch_prev, 0), R_curr = Rz(dyaw) R(roll_curr, pitch_curr, 0).
// The sum over a flight telescopes to the lever turned from the first to the
// last attitude (3 m for a 1.5 m lever and a reversed heading).

#include <Eigen/Core>

#include "processes/vo_solver/translation_solver.h"

namespace nadir::vo {

// Moves `est` (translation, altitude, and the translation's covariance with
// dyaw) from the camera to the INS reference point. A zero lever changes nothing.
void move_to_ins_reference(const FramePair& pair, const Eigen::Vector3d& camera_lever_body, Estimate* est);

}  // namespace nadir::vo
