#pragma once
// Sensor model parameters: one named set from a YAML file (default
// config/sim_sensors.yaml, set "standard"), with command-line overrides for
// the paper's noise study (Fig. 8b).

#include <array>
#include <string>

#include "common/config.h"
#include "common/options_schema.h"

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
  // Correlated yaw error (first-order Gauss-Markov, on top of the white noise
  // and the bias walk); 0 = off, no random numbers drawn.
  double yaw_gm_sigma_deg = 0.0;
  double yaw_gm_tau_s = 60.0;
};

struct AltimeterModelOptions {
  double rate_hz = 10.0;
  double noise_m = 0.1;            // range noise sigma = noise_m + noise_pct/100 * range
  double noise_pct = 0.1;
  double dropout_probability = 0.01;  // published as VALID_NO_RETURN
  double max_range_m = 2000.0;        // beyond: VALID_OUT_OF_RANGE
  // Installation errors (all 0 / 1 = an ideal installation):
  double scale = 1.0;    // reported range = scale * true range + bias_m + noise
  double bias_m = 0.0;
  // True beam = Ry(pitch) Rx(roll) of this applied to the nominal beam (the
  // configured camera's optical axis, which the altimeter still reports).
  std::array<double, 2> beam_misalignment_deg{0.0, 0.0};
  std::array<double, 3> lever_arm_m{0.0, 0.0, 0.0};  // beam origin from the INS, body frame
};

struct CameraSensorOptions {
  double trigger_jitter_us = 20.0;       // sigma of reported trigger time - true exposure time
  double frame_drop_probability = 0.003;  // trigger published, image not
  double pixel_noise_dn = 2.0;
  double exposure_us = 1500.0;
  double gain_db = 0.0;
  // Installation and intrinsic errors: the renderer's true camera differs from
  // the `camera:` config the estimator reads (all 0 / 1 = the config is exact).
  std::array<double, 3> boresight_rpy_deg{0.0, 0.0, 0.0};  // true mount = configured mount * R(rpy)
  double time_offset_us = 0.0;      // camera clock vs INS clock: exposure this long after the stamp
  double trigger_latency_us = 0.0;  // trigger edge to start of exposure (adds to the offset)
  double focal_scale = 1.0;         // true fx, fy = configured * focal_scale
  std::array<double, 5> distortion_error{0, 0, 0, 0, 0};  // true k1, k2, p1, p2, k3 = configured + this
  std::array<double, 3> lever_arm_m{0.0, 0.0, 0.0};       // camera centre from the INS, body frame
  // Exposure time minus stamp (us).
  double exposure_delay_us() const { return time_offset_us + trigger_latency_us; }
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
  static const OptionsSchema<SensorOptions>& schema();  // every key of a sensor set
  // True if any installation/intrinsic error (beyond noise) is set.
  bool has_installation_errors() const;
  // YAML text of the effective values (for CONFIG).
  std::string to_yaml() const;
};

}  // namespace nadir::sim
