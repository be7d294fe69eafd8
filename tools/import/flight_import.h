#pragma once
// A recorded flight (a photo folder, or a video with .SRT / CSV telemetry) ->
// a nadir LCM log OUT.lcmlog + the config OUT.yaml that nadir_replay and
// nadir_eval run on unchanged. Conventions: docs/own-flight.md.

#include <Eigen/Core>

#include <array>
#include <string>
#include <vector>

#include "tools/import/attitude_accuracy.h"
#include "tools/import/photo_metadata.h"
#include "tools/import/telemetry.h"
#include "tools/import/working_resolution.h"

namespace nadir::import {

// Pinhole + OpenCV radial-tangential distortion for one image size.
struct CameraIntrinsics {
  int width = 0, height = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0;
  std::vector<double> distortion = std::vector<double>(5, 0.0);  // k1 k2 p1 p2 k3
  bool has_mount = false;
  std::array<double, 3> mount_rpy_deg{0, 0, 0};
  std::string source;  // file, or "EXIF ..." / "--focal-px"
  // The same camera for images scaled by `s` (pixel centres kept).
  CameraIntrinsics scaled(double s) const;
};

// OpenCV cv::FileStorage calibration: camera_matrix, distortion_coefficients,
// image_width, image_height, optional mount_rpy_deg. Throws naming file and key.
CameraIntrinsics read_camera_file(const std::string& path);

// Default mount (body <- camera roll, pitch, yaw in degrees) per source: DJI,
// senseFly, video: the top of the image is the aircraft's forward -> [0, 0, 90].
inline constexpr std::array<double, 3> kTopForwardMount{0.0, 0.0, 90.0};

// senseFly XMP (established from the Seneca flight, docs/own-flight.md):
// body attitude = ZYX(yaw = Heading, pitch = kSenseflyPitchSign * PitchAngle,
// roll = kSenseflyRollSign * RollAngle), camera mounted with kSenseflyMount.
inline constexpr double kSenseflyRollSign = 1.0;
inline constexpr double kSenseflyPitchSign = 1.0;
inline constexpr std::array<double, 3> kSenseflyMount{0.0, 0.0, 90.0};

// DJI gimbal angles (degrees) -> world <- image camera (x columns, y rows, z optical axis).
Eigen::Matrix3d dji_world_from_camera(double roll_deg, double pitch_deg, double yaw_deg);
// body <- camera for a mount given as roll, pitch, yaw degrees (common/camera_model's convention).
Eigen::Matrix3d body_from_camera(const std::array<double, 3>& mount_rpy_deg);

struct ImportOptions {
  std::string photos_dir;        // photo mode: folder of .jpg/.jpeg/.png/.tif/.tiff
  std::string video;             // video mode: the video file ...
  std::string srt;               // ... with a DJI-style .SRT
  std::string csv;               // ... or a generic CSV
  std::string out;               // OUT -> OUT.lcmlog, OUT.yaml
  std::string camera_file;       // OpenCV calibration (empty: from the photos' metadata, photo_camera.h, with a warning)
  double focal_px = 0.0;         // > 0: focal length in pixels of the source images (overrides EXIF)
  double scale = 0.0;            // downscale factor for the images (0, 1]; 0: the working resolution's rule (working_resolution.h)
  double interval_s = 0.0;       // > 0: photo times from file order at this interval (EXIF times ignored)
  bool skip_bad = false;         // skip and count bad inputs instead of failing
  // > 0: the attitude's accuracy (1 sigma, degrees, per frame) instead of the
  // attitude source's (attitude_accuracy.h); written into the config.
  double attitude_stddev_deg = 0.0;  // roll and pitch
  double heading_stddev_deg = 0.0;
  std::string config_path;       // base config (config/default.yaml)
  bool progress = false;
  void Check() const;            // throws std::invalid_argument naming the option
};

// A photo stored turned clockwise by `degrees` against the flight, turned back (stored_turn.h).
struct TurnedPhoto {
  std::string where;
  int degrees = 0;
};

struct ImportSummary {
  std::string log_path, yaml_path;
  std::string mode;                   // photos | video
  int64_t frames_written = 0;
  std::vector<SkippedInput> skipped;  // every skipped photo / frame / record, with its reason
  double first_time_s = 0, last_time_s = 0;
  double max_gap_s = 0, median_interval_s = 0;
  double distance_m = 0;              // along the GPS track (3D)
  CameraIntrinsics camera;            // as written (after scaling)
  WorkingResolution resolution;       // the scale the images were brought to, and why
  std::string camera_model;           // EXIF Model of the photos when the camera came from them
  std::string focal_rule;             // ... and how their focal length was made (photo_camera.h)
  std::array<double, 3> mount_rpy_deg{0, 0, 0};
  std::string altimeter_source;       // rangefinder | barometric_relative
  std::string attitude_source;        // dji_gimbal | dji_flight | sensefly | srt_gimbal | srt_flight | csv_body
  AttitudeAccuracy attitude_accuracy;  // ... how well it is known, as written into the config
  std::vector<TurnedPhoto> turned_back;  // photos found stored turned (from the images), turned back
  int64_t orientation_unchecked = 0;     // photos no neighbour could be registered with: orientation as stored
  std::vector<std::string> warnings;
};

// Does the import; throws std::runtime_error naming file (and line) on bad
// input unless options.skip_bad. Never writes a log with no frame.
ImportSummary run_import(const ImportOptions& options);
std::string summary_json(const ImportSummary& summary);
std::string summary_text(const ImportSummary& summary);

}  // namespace nadir::import
