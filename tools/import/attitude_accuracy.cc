#include "tools/import/attitude_accuracy.h"

#include <cstdio>
#include <stdexcept>

namespace nadir::import {

AttitudeAccuracy attitude_accuracy_of_source(const std::string& source) {
  AttitudeAccuracy a;
  if (source == "sensefly") {
    // Measured on a senseFly fixed-wing survey (docs/own-flight.md): the
    // images' tilt against the autopilot's RollAngle / PitchAngle at the same
    // photo, robust sd 4.8 deg in roll and 2.9 deg in pitch (one figure for
    // both: their rms, 4 deg). The heading's own scatter could not be told
    // from the GPS track's at whole-second fixes; 3 deg is a small
    // autopilot's magnetometer-aided heading.
    a.roll_pitch_stddev_deg = 4.0;
    a.heading_stddev_deg = 3.0;
    a.basis = "senseFly autopilot angles at whole-second times (roll/pitch measured against the images on a survey)";
  } else if (source == "dji_gimbal" || source == "srt_gimbal") {
    // A stabilised gimbal holds the camera; its angles are the drone's AHRS
    // attitude plus the gimbal's encoders, written at the exposure. Assumed,
    // not measured on a flight here.
    a.roll_pitch_stddev_deg = 1.0;
    a.heading_stddev_deg = 3.0;
    a.basis = "DJI gimbal angles (assumed: a consumer AHRS, stabilised camera)";
  } else if (source == "dji_flight" || source == "srt_flight") {
    // The aircraft's own angles with the camera fixed to it. Assumed.
    a.roll_pitch_stddev_deg = 2.0;
    a.heading_stddev_deg = 3.0;
    a.basis = "DJI flight-controller angles (assumed: a consumer AHRS, camera fixed to the body)";
  } else if (source == "csv_body") {
    // A CSV carries whatever the user logged, often an INS: the base
    // config's figures describe one.
    a.from_base_config = true;
    a.basis = "CSV telemetry (the base config's INS figures; give --attitude-stddev-deg for another source)";
  } else {
    throw std::invalid_argument("no attitude accuracy known for attitude source '" + source + "'");
  }
  return a;
}

AttitudeAccuracy attitude_accuracy(const std::string& source, double roll_pitch_stddev_deg,
                                   double heading_stddev_deg) {
  AttitudeAccuracy a = attitude_accuracy_of_source(source);
  if (roll_pitch_stddev_deg <= 0.0 && heading_stddev_deg <= 0.0) return a;
  // Only what the user gave is written where the source had no figures: the
  // other stays the base config's (0 here).
  a.from_base_config = false;
  if (roll_pitch_stddev_deg > 0.0) a.roll_pitch_stddev_deg = roll_pitch_stddev_deg;
  if (heading_stddev_deg > 0.0) a.heading_stddev_deg = heading_stddev_deg;
  a.basis = "as given (--attitude-stddev-deg / --heading-stddev-deg) over: " + a.basis;
  return a;
}

std::string describe(const AttitudeAccuracy& a) {
  if (a.from_base_config) return "the base config's; " + a.basis;
  auto figure = [](double deg) {
    if (!(deg > 0.0)) return std::string("the base config's");
    char text[32];
    std::snprintf(text, sizeof(text), "%.2f deg", deg);
    return std::string(text);
  };
  return "roll/pitch " + figure(a.roll_pitch_stddev_deg) + ", heading " + figure(a.heading_stddev_deg) + " (1 sigma): " +
         a.basis;
}

}  // namespace nadir::import
