#pragma once
// Small helpers shared by the simulator's tests.

#include <string>

#include "common/config.h"
#include "processes/sim/flight_profile.h"
#include "processes/sim/sensor_options.h"
#include "processes/sim/sim_camera.h"

namespace nadir::sim::testing {

inline std::string source_path(const std::string& relative) { return std::string(NADIR_SOURCE_DIR) + "/" + relative; }
inline SimCamera default_camera() { return SimCamera::from_config(Config::load_file(source_path("config/default.yaml"))); }
inline FlightProfile profile(const std::string& name) {
  return FlightProfile::load(source_path("config/profiles/" + name + ".yaml"));
}
inline SensorOptions sensor_set(const std::string& name) {
  return SensorOptions::from_config(Config::load_file(source_path("config/sim_sensors.yaml")), name);
}

}  // namespace nadir::sim::testing
