#pragma once
// Sensor model parameters: one named set from a YAML file (default
// config/sim_sensors.yaml, set "standard"), with command-line overrides for
// the paper's noise study (Fig. 8b).

#include <string>

#include "common/config.h"

namespace nadir::sim {

struct InsModelOptions {
  double rate_hz = 100.0;
  double roll_pitch_noise_deg = 0.05;         // white noise sigma on roll and pitch
  double yaw_noise_deg = 0.1;                 // white noise sigma on yaw
  double yaw_bias_initial_deg = 0.0;          // yaw bias at the start
  double yaw_bias_walk_deg_per_sqrt_s = 0.004;  // random-walk drift of the yaw bias
  // Correlated roll/pitch errors (first-order Gauss-Markov, independent per
  // axis, added to the white noise): stationary sigma and correlation time.
  // 0 = off, and then no random numbers are drawn (existing sets unchanged).
  double roll_pitch_gm_sigma_deg = 0.0;
  double roll_pitch_gm_tau_s = 60.0;
};

struct AltimeterModelOptions {
  double rate_hz = 10.0;
  double noise_m = 0.1;            // range noise sigma = noise_m + noise_pct/100 * range
  double noise_pct = 0.1;
  double dropout_probability = 0.01;  // published as VALID_NO_RETURN
  double max_range_m = 2000.0;        // beyond: VALID_OUT_OF_RANGE
};

struct CameraSensorOptions {
  double trigger_jitter_us = 20.0;       // sigma of reported trigger time - true exposure time
  double frame_drop_probability = 0.003;  // trigger published, image not
  double pixel_noise_dn = 2.0;
  double exposure_us = 1500.0;
  double gain_db = 0.0;
};

struct SensorOptions {
  std::string set_name = "standard";
  std::string source;
  InsModelOptions ins;
  AltimeterModelOptions altimeter;
  CameraSensorOptions camera;

  // Reads set `set_name` of a sensor file; errors name the file and key.
  static SensorOptions from_config(const Config& root, const std::string& set_name);
  // Throws ConfigError naming the option when a value is out of range.
  void Check() const;
  // YAML text of the effective values (for CONFIG).
  std::string to_yaml() const;
};

}  // namespace nadir::sim
