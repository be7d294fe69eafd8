#pragma once
// Installation calibration from a flight segment with a position/attitude
// reference (INS with GNSS) and camera feature tracks (TRACKS, from replaying
// the tracker over the flight): camera-body boresight, camera-INS time offset
// and focal length scale by an epipolar fit; altimeter scale and bias by a
// regression of the measured range against the height above ground along the
// beam. Method and the flight it needs: docs/calibration.md.

#include <array>
#include <limits>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "common/config.h"
#include "common/sensor_calibration.h"
#include "tools/calibrate/gps_scale.h"

namespace nadir::calibrate {

struct CalibrationOptions {
  // Half-width (s) of the centred average over the INS attitude error
  // relative to the integrated INS body rates, in the world frame (the rates
  // carry the motion, the attitude the absolute level: neither the white
  // attitude noise nor the averaging reaches the motion). Without rates: over
  // the attitude itself. What the average leaves of the noise steps by
  // noise / (2 h + 1) from one INS sample to the next; with +-1 s that pulled
  // the time offset 1-3 % short (README, "Accuracy reached"), with +-3 s it
  // is within its sigma. A centred average
  // cancels a gyro bias's linear drift, so only gyro errors that change
  // within the window (scale factor in turns) limit it.
  double attitude_smoothing_s = 3.0;
  double min_baseline_m = 1.0;   // frame pairs with a shorter baseline carry no direction
  double cluster_s = 2.0;        // residuals within this span share INS errors (robust covariance)
  double jackknife_block_s = 10.0;  // blocks left out in turn for the jackknife sigmas
  int bootstrap_runs = 12;  // refits against redrawn INS attitude noise (0 = none)
  double outlier_sigma = 4.0;    // residuals beyond this many robust sigmas are dropped
  int iterations = 6;            // Gauss-Newton iterations
  bool estimate_focal = true;    // fit the focal length scale (fixed at 1 when unobservable)
  // With the focal scale: fit the errors of the radial distortion
  // coefficients k1 and k2 too (held at 0 when unobservable). A lens
  // calibrated in the lab is seldom exact; an unfitted error is absorbed by
  // the focal scale and, through the vertical, by the boresight pitch.
  // Written into the fragment's camera.distortion.
  bool estimate_distortion = true;
  // Height of flat ground (m, the INS height datum) for the altimeter
  // regression when the log has no GROUND_TRUTH; NaN = none.
  double ground_height_m = std::numeric_limits<double>::quiet_NaN();
  // With GROUND_TRUTH: the terrain height under the altimeter beam's
  // footprint is taken from the nearest point of the vehicle's track; ranges
  // whose footprint lies farther than this (m) from the track are not used.
  double altimeter_max_offtrack_m = 10.0;
  // The INS attitude's own slowly varying error (deg, roll/pitch/yaw, e.g.
  // from its datasheet): the boresight is estimated relative to the INS's
  // attitude, so its mean error over the segment is not seen in the residuals
  // and is added to the boresight sigmas.
  std::array<double, 3> ins_attitude_accuracy_deg{0.0, 0.0, 0.0};
  // Correlation time (s) of that error, a first-order Gauss-Markov process
  // (e.g. 60 s): over a segment of length T its mean has the sigma
  // ins_attitude_sigma_of_mean(). 0: a constant bias, the accuracy itself.
  double ins_attitude_correlation_s = 0.0;
  // A parameter whose sigma exceeds its limit is reported as not excited.
  double boresight_sigma_limit_deg = 0.05;
  double time_offset_sigma_limit_ms = 1.0;
  double focal_sigma_limit = 0.002;
  double distortion_sigma_limit = 0.002;  // of k1
  double altimeter_scale_sigma_limit = 0.003;
  double altimeter_bias_sigma_limit_m = 0.3;
  // The image scale against GNSS (tools/calibrate/gps_scale.h), from the
  // log's VO_DELTA: always reported when the log has them; written into the
  // fragment as a focal length (kFocal) or an altimeter scale (kAltimeter)
  // when asked. The VO_DELTA must come from the config given as camera_root.
  enum class GpsScaleTarget { kReport, kFocal, kAltimeter };
  GpsScaleTarget gps_scale_target = GpsScaleTarget::kReport;
  bool gps_scale_only = false;  // the fragment sets only what the GNSS scale gives (a survey flight)
  double gps_scale_min_baseline_m = 2.0;  // shorter GNSS baselines carry too much of the GNSS noise
  // The segment of the flight used (s after the log's first INS sample);
  // the rest is left for checking the result on data it was not fitted on.
  double segment_from_s = 0.0;
  double segment_until_s = std::numeric_limits<double>::infinity();
  void Check() const;  // throws ConfigError naming the option
};

// One estimated quantity with its 1-sigma uncertainty.
struct Estimate {
  std::string name;  // e.g. boresight_roll_deg
  double value = 0.0;
  double sigma = 0.0;
  bool estimated = false;  // false: held at its nominal value (not observable or no data)
  bool excited = false;    // sigma within its limit
};

// The data of a flight segment, read from a log.
struct FlightData {
  struct InsSample {
    int64_t utime;
    double roll, pitch, yaw;
    bool has_rates;
    Eigen::Vector3d angular_rate;  // body frame, rad/s
    Eigen::Vector3d position_ned;  // from latitude/longitude/height about the first sample
  };
  struct FramePair {
    int64_t prev_utime, utime;
    std::vector<Eigen::Vector2d> prev_norm, curr_norm;  // undistorted normalized (configured camera)
  };
  struct AltimeterSample {
    int64_t utime;
    double range_m;
    Eigen::Vector3d beam_body;
  };
  struct TerrainSample {  // GROUND_TRUTH (KIND_INS): the ground under the vehicle
    int64_t utime;
    Eigen::Vector3d position_ned;  // the truth's own NED frame
    double terrain_height_m;
  };
  std::vector<InsSample> ins;
  std::vector<FramePair> pairs;
  std::vector<AltimeterSample> altimeter;
  std::vector<TerrainSample> terrain;  // if the log has GROUND_TRUTH
  std::vector<VoStep> vo_steps;        // if the log has VO_DELTA (a replay through vo_solver)
  double reference_height_m = 0.0;  // INS height of the first sample (the NED origin)
  int64_t corrupt_records = 0;
};

// Reads INS, TRACKS, ALTIMETER (VALID_OK) and GROUND_TRUTH; throws
// std::runtime_error naming the file when it lacks what the fit needs.
FlightData load_flight(const std::string& log_path, bool progress);

struct CalibrationResult {
  std::array<Estimate, 3> boresight;  // roll, pitch, yaw (deg), about the configured mount
  Estimate time_offset_ms;            // exposure = image stamp + offset
  Estimate focal_scale;               // true focal length / configured
  Estimate distortion_k1_error;       // true k1 - configured k1
  Estimate distortion_k2_error;       // true k2 - configured k2 (fitted with k1)
  // The lens distortion the fragment writes: the configured one, with the
  // fitted k1, k2 errors added when both are excited (`distortion_fitted`).
  // Always written, so that a second pass about the first's values carries
  // them on.
  std::vector<double> distortion;
  bool distortion_fitted = false;
  Estimate altimeter_scale;           // measured = scale * true range + bias
  Estimate altimeter_bias_m;
  Estimate gps_scale;                 // GNSS baseline / VO step (not estimated without VO_DELTA)
  int64_t gps_scale_pairs = 0;
  Estimate heading_offset_deg;        // image heading - recorded yaw over the same pairs (deg)
  bool heading_offset_applied = false;  // scale-only fragment: written into the mount's yaw (beyond 3 sigma)
  Eigen::Vector3d configured_mount_rpy_deg = Eigen::Vector3d::Zero();
  CalibrationOptions::GpsScaleTarget gps_scale_target = CalibrationOptions::GpsScaleTarget::kReport;
  Eigen::Vector3d mount_rpy_deg = Eigen::Vector3d::Zero();  // configured mount composed with the boresight
  double fx = 0, fy = 0;              // configured focal lengths times the focal scale (or over the GNSS scale)
  double range_scale = 1.0;           // altimeter.range_scale written into the fragment
  double range_bias_m = 0.0;          // altimeter.range_bias_m written (fitted, else as configured)
  bool scale_only = false;            // the fragment holds only the GNSS scale's keys
  SensorCalibration installation;     // as configured: its lever arms and beam are echoed in the fragment
  int64_t frame_pairs = 0, residuals = 0, outliers = 0, altimeter_samples = 0;
  double camera_rms_rad = 0.0, altimeter_rms_m = 0.0;
  double segment_s = 0.0;
  std::vector<std::string> warnings;  // observability and data warnings

  // The YAML config fragment (camera: / altimeter:) with sigmas in comments.
  std::string config_fragment(const std::string& source) const;
  std::string json() const;
};

// Fits everything the data allows. `camera_root` holds the configured
// Standard deviation of the mean over `segment_s` of a first-order
// Gauss-Markov process with standard deviation `sigma` and correlation time
// `correlation_s` (0: a constant, `sigma` itself):
// sigma^2 (2 tau / T) (1 - (tau / T)(1 - exp(-T / tau))).
double ins_attitude_sigma_of_mean(double sigma, double correlation_s, double segment_s);

// The shortest segment (s) whose mean of that process has at most `target`
// standard deviation: 0 when `sigma` is within it already, infinity when no
// segment gets there (a constant error, or a target of 0).
double segment_for_ins_sigma_of_mean(double sigma, double correlation_s, double target);

// `camera:` section (intrinsics and mount the TRACKS were normalized with).
CalibrationResult calibrate(const FlightData& data, const Config& camera_root, const CalibrationOptions& options);

}  // namespace nadir::calibrate
