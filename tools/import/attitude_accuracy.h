#pragma once
// How well a recorded flight's attitude is known, by where the import took it
// from. A drone's photo metadata is not an INS: a fixed-wing autopilot writes
// its roll, pitch and heading at whole-second times while the aircraft banks
// between photos, and a gimbal's angles come from the drone's own AHRS. The
// estimator's sensor uncertainty (vo_solver.uncertainty, yaw_fusion's INS yaw)
// must say so, or every pair's covariance, and with it the reported sigma and
// protection level, describes an INS the flight never had.

#include <string>

namespace nadir::import {

// The largest figure --attitude-stddev-deg / --heading-stddev-deg take.
inline constexpr double kMaxAttitudeStddevDeg = 30.0;
// The largest vo_solver.feature_depth.ins_tilt_sigma_deg its options accept
// (feature_depth_solver.cc); a tilt prior that wide leaves the tilt to the images.
inline constexpr double kMaxTiltPriorDeg = 5.0;

struct AttitudeAccuracy {
  double roll_pitch_stddev_deg = 0.0;  // per photo / frame, white
  double heading_stddev_deg = 0.0;     // per photo / frame, white
  std::string basis;                   // where the figures come from, for the summary
  bool from_base_config = false;       // true: the base config's figures are kept (nothing written)
};

// The accuracy of an attitude source (flight_import.h, ImportSummary::attitude_source):
// sensefly, dji_gimbal, dji_flight, srt_gimbal, srt_flight, csv_body. Throws
// std::invalid_argument for an unknown source.
AttitudeAccuracy attitude_accuracy_of_source(const std::string& attitude_source);

// The source's accuracy with the user's figures over it: a value > 0 replaces
// the source's (roll_pitch_stddev_deg, heading_stddev_deg; 0 keeps it).
AttitudeAccuracy attitude_accuracy(const std::string& attitude_source, double roll_pitch_stddev_deg,
                                   double heading_stddev_deg);

// One line for the import's summary: the figures and their basis.
std::string describe(const AttitudeAccuracy& accuracy);

}  // namespace nadir::import
