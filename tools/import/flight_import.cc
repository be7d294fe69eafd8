#include "tools/import/flight_import.h"

#include <yaml-cpp/yaml.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <optional>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>
#include <stdexcept>
#include <tuple>

#include "common/channels.h"
#include "common/geodetic.h"
#include "common/geometry.h"
#include "common/json_writer.h"
#include "common/log_file.h"
#include "common/message_guard.h"
#include "common/options_schema.h"
#include "common/progress.h"
#include "common/robust_stats.h"
#include "nadir/altimeter_t.hpp"
#include "nadir/config_t.hpp"
#include "nadir/ground_truth_t.hpp"
#include "nadir/image_t.hpp"
#include "nadir/ins_t.hpp"
#include "tools/import/photo_camera.h"
#include "tools/import/stored_turn.h"

namespace nadir::import {
namespace {

namespace fs = std::filesystem;

constexpr double kDefaultEpochS = 1000.0;  // sensor time of the first frame when the source has no clock

// One frame to write, before its image is read.
struct Sample {
  std::string where;            // file, or "VIDEO frame N (TELEMETRY:LINE)"
  std::string image_path;       // photo mode
  int64_t video_frame = -1;     // video mode
  double time_s = 0;
  Eigen::Matrix3d world_from_body = Eigen::Matrix3d::Identity();
  double lat_deg = 0, lon_deg = 0;
  bool has_alt = false;
  double alt_m = 0;
  double height_m = 0;          // altimeter value (vertical)
  std::string height_kind;      // rangefinder | barometric_relative
  PhotoMetadata photo;          // photo mode: what the file says (its camera when none is given)
};

void skip_or_throw(bool skip_bad, const std::string& where, const std::string& reason,
                   std::vector<SkippedInput>* skipped) {
  if (!skip_bad) throw std::runtime_error(where + ": " + reason);
  skipped->push_back({where, reason});
}

bool is_image_file(const fs::path& p) {
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext == ".jpg" || ext == ".jpeg" || ext == ".png" || ext == ".tif" || ext == ".tiff";
}

// Photo metadata -> sample; false with `why` when time, attitude, GPS or height is missing.
bool photo_sample(const PhotoMetadata& m, const ImportOptions& o, const std::array<double, 3>& mount, Sample* s,
                  std::string* attitude_source, std::string* why) {
  s->where = m.path;
  s->image_path = m.path;
  s->photo = m;
  if (o.interval_s <= 0.0) {
    if (m.has_time) {
      s->time_s = m.time_s;
    } else if (m.has_sensefly_time) {
      s->time_s = m.sf_utc_s;
    } else {
      *why = "no time (Exif.Photo.DateTimeOriginal missing; give --interval to use file order)";
      return false;
    }
  }
  if (m.has_dji_gimbal) {
    s->world_from_body = dji_world_from_camera(m.gimbal_roll_deg, m.gimbal_pitch_deg, m.gimbal_yaw_deg) *
                         body_from_camera(mount).transpose();
    *attitude_source = "dji_gimbal";
  } else if (m.has_dji_flight) {
    s->world_from_body = rotation_from_rpy(deg_to_rad(m.flight_roll_deg), deg_to_rad(m.flight_pitch_deg),
                                           deg_to_rad(m.flight_yaw_deg));
    *attitude_source = "dji_flight";
  } else if (m.has_sensefly_attitude) {
    s->world_from_body = rotation_from_rpy(deg_to_rad(kSenseflyRollSign * m.sf_roll_deg),
                                           deg_to_rad(kSenseflyPitchSign * m.sf_pitch_deg),
                                           deg_to_rad(m.sf_heading_deg));
    *attitude_source = "sensefly";
  } else {
    *why = "no attitude (neither drone-dji Gimbal/Flight angles nor sensefly RollAngle/PitchAngle/Heading)";
    return false;
  }
  if (m.has_gps) {
    s->lat_deg = m.lat_deg;
    s->lon_deg = m.lon_deg;
  } else if (m.has_sensefly_position) {
    s->lat_deg = m.sf_lat_deg;
    s->lon_deg = m.sf_lon_deg;
  } else {
    *why = "no GPS position (Exif.GPSInfo or sensefly Latitude/Longitude)";
    return false;
  }
  if (m.has_dji_absolute_alt) {
    s->has_alt = true, s->alt_m = m.dji_absolute_alt_m;
  } else if (m.has_sensefly_alt) {
    s->has_alt = true, s->alt_m = m.sf_alt_m;
  } else if (m.has_gps_alt) {
    s->has_alt = true, s->alt_m = m.gps_alt_m;
  }
  if (m.has_dji_relative_alt) {
    s->height_m = m.dji_relative_alt_m;
  } else if (m.has_sensefly_height) {
    s->height_m = m.sf_height_m;
  } else {
    *why = "no height above take-off (drone-dji RelativeAltitude or sensefly Height)";
    return false;
  }
  s->height_kind = "barometric_relative";
  return true;
}

// One camera per flight: the model and size most of the folder's photos have.
struct FlightCamera {
  const PhotoMetadata* first = nullptr;  // the first photo of it
  int count = 0, of = 0;                 // photos of it, of all read
};

FlightCamera most_common_camera(const std::vector<PhotoMetadata>& metadata, const std::vector<std::string>& read_error) {
  std::map<std::tuple<std::string, int, int>, std::pair<int, size_t>> seen;  // -> count, first index
  FlightCamera best;
  for (size_t i = 0; i < metadata.size(); ++i) {
    if (!read_error[i].empty()) continue;
    ++best.of;
    const PhotoMetadata& m = metadata[i];
    auto& entry = seen.try_emplace({m.model, m.image_width, m.image_height}, 0, i).first->second;
    ++entry.first;
  }
  size_t best_index = 0;
  for (const auto& [key, entry] : seen) {
    if (entry.first > best.count || (entry.first == best.count && entry.second < best_index)) {
      best.count = entry.first;
      best_index = entry.second;
    }
  }
  if (best.count > 0) best.first = &metadata[best_index];
  return best;
}

// A photo whose EXIF Model or size differs from the flight camera's is named
// with both (a folder of mixed cameras or sizes).
bool same_camera(const FlightCamera& flight, const PhotoMetadata& m, std::string* why) {
  if (!flight.first) return true;
  const PhotoMetadata& first = *flight.first;
  const std::string others = " (" + std::to_string(flight.count) + " of the " + std::to_string(flight.of) +
                             " photos, the first " + first.path + ")";
  const auto name = [](const PhotoMetadata& p) { return p.model.empty() ? std::string("(no EXIF Model)") : "'" + p.model + "'"; };
  if (m.model != first.model) {
    *why = "camera model " + name(m) + " differs from the flight's " + name(first) + others +
           ": one camera per import, mixed cameras in the folder";
    return false;
  }
  // A photo stored turned by a quarter turn has the size transposed: the same camera.
  const bool same_size = (m.image_width == first.image_width && m.image_height == first.image_height) ||
                         (m.image_width == first.image_height && m.image_height == first.image_width);
  if (m.image_width > 0 && first.image_width > 0 && !same_size) {
    *why = "photo is " + std::to_string(m.image_width) + "x" + std::to_string(m.image_height) +
           " but the flight's are " + std::to_string(first.image_width) + "x" + std::to_string(first.image_height) +
           others + ": one image size per import, mixed sizes in the folder";
    return false;
  }
  return true;
}

bool telemetry_sample(const TelemetryRecord& r, const std::array<double, 3>& mount, Sample* s,
                      std::string* attitude_source) {
  if (r.has_gimbal) {
    s->world_from_body =
        dji_world_from_camera(r.gimbal_roll_deg, r.gimbal_pitch_deg, r.gimbal_yaw_deg) * body_from_camera(mount).transpose();
    *attitude_source = "srt_gimbal";
  } else if (r.has_body) {
    s->world_from_body = rotation_from_rpy(deg_to_rad(r.roll_deg), deg_to_rad(r.pitch_deg), deg_to_rad(r.yaw_deg));
    *attitude_source = r.frame >= 0 ? "srt_flight" : "csv_body";
  } else {
    return false;
  }
  s->lat_deg = r.lat_deg;
  s->lon_deg = r.lon_deg;
  s->has_alt = r.has_alt;
  s->alt_m = r.alt_m;
  if (r.has_range) {
    s->height_m = r.range_m;
    s->height_kind = "rangefinder";
  } else {
    s->height_m = r.height_m;
    s->height_kind = "barometric_relative";
  }
  return true;
}

// Local NED along the path from the origin sample (common/geodetic.h), every
// sample converted once in order: forward from the origin, and backward for
// the samples before it (skipped frames still give neighbours' velocity).
// Down from the relative height when every sample has one kind of altitude
// ... see README.
struct LocalFrame {
  bool use_alt = false;
  std::vector<Eigen::Vector3d> positions;
  LocalFrame(const std::vector<Sample>& samples, size_t origin, bool use_alt_) : use_alt(use_alt_) {
    const GeodeticPoint start = point(samples[origin]);
    GeodeticTrack forward(start), backward(start);
    positions.resize(samples.size());
    for (size_t j = origin; j < samples.size(); ++j) positions[j] = forward.ned(point(samples[j]));
    for (size_t j = origin; j-- > 0;) positions[j] = backward.ned(point(samples[j]));
  }
  GeodeticPoint point(const Sample& s) const { return {s.lat_deg, s.lon_deg, use_alt ? s.alt_m : s.height_m}; }
  const Eigen::Vector3d& ned(size_t index) const { return positions[index]; }
};

template <class Msg>
void write_message(LogWriter* w, int64_t utime, const char* channel, const Msg& msg) {
  const std::vector<uint8_t> data = encode_message(msg);
  w->write(utime, channel, data.data(), data.size());
}

std::vector<double> as_vector(const std::array<double, 3>& a) { return {a[0], a[1], a[2]}; }

// The attitude's accuracy into every key that describes the INS the
// estimator is given: each pair's sensor covariance (roll/pitch, and the
// heading for the flow variant), feature_depth's tilt prior (at most
// kMaxTiltPriorDeg, where the images already set the tilt) and yaw fusion's
// INS heading. A zero figure keeps the base config's.
void write_attitude_accuracy(const AttitudeAccuracy& a, YAML::Node* root) {
  if (a.from_base_config) return;
  YAML::Node vo = (*root)["vo_solver"];
  if (a.roll_pitch_stddev_deg > 0.0) {
    vo["uncertainty"]["roll_pitch_stddev_deg"] = a.roll_pitch_stddev_deg;
    vo["feature_depth"]["ins_tilt_sigma_deg"] = std::min(a.roll_pitch_stddev_deg, kMaxTiltPriorDeg);
  }
  if (a.heading_stddev_deg > 0.0) {
    vo["uncertainty"]["yaw_stddev_deg"] = a.heading_stddev_deg;
    YAML::Node yf = (*root)["yaw_fusion"];
    yf["ins_yaw_stddev_deg"] = a.heading_stddev_deg;
    const double max_used = yf["max_ins_yaw_stddev_deg"] ? yf["max_ins_yaw_stddev_deg"].as<double>() : 0.0;
    if (max_used < a.heading_stddev_deg) yf["max_ins_yaw_stddev_deg"] = a.heading_stddev_deg;
  }
}

// config/default.yaml with the camera and the overrides a sparse frame stream needs.
std::string output_yaml(const ImportOptions& o, const ImportSummary& s) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(o.config_path);
  } catch (const YAML::Exception& e) {
    throw std::runtime_error(o.config_path + ": cannot read base config: " + e.what());
  }
  const CameraIntrinsics& c = s.camera;
  YAML::Node cam = root["camera"];
  cam["width"] = c.width;
  cam["height"] = c.height;
  cam["fx"] = c.fx;
  cam["fy"] = c.fy;
  cam["cx"] = c.cx;
  cam["cy"] = c.cy;
  cam["distortion"] = c.distortion;
  cam["mount_rpy_deg"] = as_vector(s.mount_rpy_deg);
  cam["rate_hz"] = std::clamp(s.median_interval_s > 0 ? 1.0 / s.median_interval_s : 14.0, 0.1, 1000.0);
  // Longest gap between written frames, with margin: every limit on the time
  // between two frames (or between a frame and the newest input) must pass it.
  const double gap = std::min(3600.0, std::max(1.0, 1.5 * s.max_gap_s + 1.0));
  root["tracker"]["mode"] = "descriptor";
  root["tracker"]["max_gap_s"] = gap;
  // A photo stream's intervals are irregular (no photos in turns, pauses):
  // none of them is a lost frame, so no step up to the longest is flagged as
  // a frame gap (the tracker flags steps over gap_factor camera periods). A
  // video's frames are regular: a gap there is a real one.
  if (!o.photos_dir.empty()) {
    root["tracker"]["gap_factor"] = std::clamp(gap * cam["rate_hz"].as<double>(), 1.5, 100.0);
  }
  root["vo_solver"]["sync"]["max_frame_interval_ms"] = gap * 1000.0;
  root["yaw_fusion"]["max_delta_interval_s"] = gap;
  root["yaw_fusion"]["max_time_jump_s"] = gap;
  root["input_checks"]["max_ahead_s"] = gap;
  root["input_checks"]["max_behind_s"] = gap;
  // A barometric height above take-off (DJI RelativeAltitude) is an altitude,
  // not a range to the ground: down follows it (processes/yaw_fusion/README.md
  // § Altitude), with an assumed 0.3 m of noise per photo (DJI writes it to
  // 0.1 m). A height beyond 3 sigma of the integrated down says the pair's dz
  // is wrong (a photo pair's dz is less certain than its covariance says; a
  // pair solved with an unknown lens distortion), not the barometer: down
  // goes back to the barometer at once. A rangefinder flight keeps the base
  // config's mode.
  if (s.altimeter_source == "barometric_relative") {
    root["yaw_fusion"]["altitude_mode"] = "barometric";
    root["yaw_fusion"]["altimeter_stddev_m"] = 0.3;
    root["yaw_fusion"]["altimeter_stddev_fraction"] = 0.0;
    root["yaw_fusion"]["altimeter_gate_sigma"] = 3.0;
    root["yaw_fusion"]["altimeter_max_consecutive_rejections"] = 1;
  }
  write_attitude_accuracy(s.attitude_accuracy, &root);
  YAML::Emitter out;
  out.SetDoublePrecision(12);
  out << root;
  return std::string("# Written by nadir_import from ") + (o.photos_dir.empty() ? o.video : o.photos_dir) +
         " (base: " + o.config_path + ")\n" + out.c_str() + "\n";
}

std::string config_message_yaml(const ImportOptions& o, const ImportSummary& s) {
  YAML::Node n;
  n["mode"] = s.mode;
  n["source"] = o.photos_dir.empty() ? o.video : o.photos_dir;
  if (!o.srt.empty()) n["srt"] = o.srt;
  if (!o.csv.empty()) n["csv"] = o.csv;
  n["camera_source"] = s.camera.source;
  if (!s.focal_rule.empty()) {
    n["camera_model"] = s.camera_model;
    n["focal_rule"] = s.focal_rule;
  }
  n["scale"] = s.resolution.scale;
  n["scale_rule"] = s.resolution.rule;
  n["interval_s"] = o.interval_s;
  n["skip_bad"] = o.skip_bad;
  n["skipped"] = static_cast<int64_t>(s.skipped.size());
  for (const SkippedInput& k : s.skipped) n["skipped_inputs"].push_back(k.where + ": " + k.reason);
  n["altimeter_source"] = s.altimeter_source;
  n["attitude_source"] = s.attitude_source;
  n["mount_rpy_deg"] = as_vector(s.mount_rpy_deg);
  YAML::Emitter out;
  out << n;
  return out.c_str();
}

// Exif focal length -> intrinsics of a `width` x `height` image (no distortion).
CameraIntrinsics camera_from_focal(double focal_px, int width, int height, const std::string& source) {
  CameraIntrinsics c;
  c.width = width;
  c.height = height;
  c.fx = c.fy = focal_px;
  c.cx = (width - 1) / 2.0;
  c.cy = (height - 1) / 2.0;
  c.source = source;
  return c;
}

}  // namespace

CameraIntrinsics CameraIntrinsics::scaled(double s) const {
  CameraIntrinsics c = *this;
  c.width = static_cast<int>(std::lround(width * s));
  c.height = static_cast<int>(std::lround(height * s));
  const double sx = static_cast<double>(c.width) / width, sy = static_cast<double>(c.height) / height;
  c.fx = fx * sx;
  c.fy = fy * sy;
  c.cx = (cx + 0.5) * sx - 0.5;
  c.cy = (cy + 0.5) * sy - 0.5;
  return c;
}

CameraIntrinsics read_camera_file(const std::string& path) {
  cv::FileStorage fs;
  try {
    if (!fs.open(path, cv::FileStorage::READ)) throw std::runtime_error(path + ": cannot open camera calibration");
  } catch (const cv::Exception& e) {
    throw std::runtime_error(path + ": not an OpenCV calibration file: " + e.what());
  }
  // What nadir reads, and what OpenCV's calibration tools write beside it
  // (read by nothing here, but not a misspelling): any other key is refused.
  static const std::vector<std::string> kRead{"image_width", "image_height", "camera_matrix",
                                              "distortion_coefficients", "mount_rpy_deg"};
  static const std::vector<std::string> kOpenCv{
      "calibration_time", "calibration_Time", "nr_of_frames", "nframes", "board_width", "board_height",
      "board_Width", "board_Height", "square_size", "square_Size", "aspect_ratio", "aspectRatio", "flags",
      "flagValue", "fisheye_model", "avg_reprojection_error", "per_view_reprojection_errors",
      "extrinsic_parameters", "image_points", "grid_points", "marker_size"};
  for (const std::string& key : fs.root().keys()) {
    if (std::find(kRead.begin(), kRead.end(), key) != kRead.end()) continue;
    if (std::find(kOpenCv.begin(), kOpenCv.end(), key) != kOpenCv.end()) continue;
    const std::string near = nearest_key(key, kRead);
    throw std::runtime_error(path + ": key '" + key + "' is not a known key" +
                             (near.empty() ? std::string() : "; did you mean " + near + "?"));
  }
  CameraIntrinsics c;
  c.source = path;
  cv::Mat k, d;
  fs["camera_matrix"] >> k;
  fs["distortion_coefficients"] >> d;
  if (k.rows != 3 || k.cols != 3) throw std::runtime_error(path + ": key 'camera_matrix' must be a 3x3 matrix");
  if (d.total() != 4 && d.total() != 5) {
    throw std::runtime_error(path + ": key 'distortion_coefficients' must hold 4 or 5 values (k1 k2 p1 p2 [k3])");
  }
  k.convertTo(k, CV_64F);
  d.convertTo(d, CV_64F);
  c.fx = k.at<double>(0, 0);
  c.fy = k.at<double>(1, 1);
  c.cx = k.at<double>(0, 2);
  c.cy = k.at<double>(1, 2);
  for (size_t i = 0; i < d.total(); ++i) c.distortion[i] = d.at<double>(static_cast<int>(i));
  fs["image_width"] >> c.width;
  fs["image_height"] >> c.height;
  if (c.width <= 0 || c.height <= 0) throw std::runtime_error(path + ": keys 'image_width'/'image_height' must be > 0");
  if (!(c.fx > 0 && c.fy > 0)) throw std::runtime_error(path + ": key 'camera_matrix' has a focal length <= 0");
  const cv::FileNode mount = fs["mount_rpy_deg"];
  if (!mount.empty()) {
    std::vector<double> m;
    mount >> m;
    if (m.size() != 3) throw std::runtime_error(path + ": key 'mount_rpy_deg' must list roll, pitch, yaw (degrees)");
    for (int i = 0; i < 3; ++i) {
      if (!(std::abs(m[i]) <= 180.0)) throw std::runtime_error(path + ": key 'mount_rpy_deg' values must be in [-180, 180]");
      c.mount_rpy_deg[i] = m[i];
    }
    c.has_mount = true;
  }
  return c;
}

Eigen::Matrix3d dji_world_from_camera(double roll_deg, double pitch_deg, double yaw_deg) {
  // Gimbal frame: x optical axis, y right, z down. Image camera: x = gimbal y,
  // y = gimbal z, z = gimbal x (columns are the camera's ... see README).
  Eigen::Matrix3d gimbal_from_camera;
  gimbal_from_camera << 0, 0, 1,  //
      1, 0, 0,                    //
      0, 1, 0;
  return rotation_from_rpy(deg_to_rad(roll_deg), deg_to_rad(pitch_deg), deg_to_rad(yaw_deg)) * gimbal_from_camera;
}

Eigen::Matrix3d body_from_camera(const std::array<double, 3>& m) {
  return rotation_from_rpy(deg_to_rad(m[0]), deg_to_rad(m[1]), deg_to_rad(m[2]));
}

void ImportOptions::Check() const {
  const int sources = !photos_dir.empty() + !video.empty();
  if (sources != 1) throw std::invalid_argument("give exactly one of --photos DIR or --video FILE");
  if (!video.empty() && srt.empty() == csv.empty()) throw std::invalid_argument("--video needs exactly one of --srt FILE or --csv FILE");
  if (video.empty() && (!srt.empty() || !csv.empty())) throw std::invalid_argument("--srt/--csv go with --video");
  if (out.empty()) throw std::invalid_argument("--out is required");
  if (!(scale == 0.0 || (scale > 0.0 && scale <= 1.0))) {
    throw std::invalid_argument("--scale must be in (0, 1] (1: full size; without it: the working resolution's rule)");
  }
  if (!(focal_px >= 0.0 && focal_px < 1e6)) throw std::invalid_argument("--focal-px must be in [0, 1e6)");
  if (!(interval_s >= 0.0 && interval_s <= 3600.0)) throw std::invalid_argument("--interval must be in [0, 3600] s");
  if (!video.empty() && interval_s > 0.0) throw std::invalid_argument("--interval is for --photos only");
  if (config_path.empty()) throw std::invalid_argument("a base config is required");
  // 0: not given (the attitude source's figure).
  for (const auto& [value, option] : {std::pair<double, const char*>{attitude_stddev_deg, "--attitude-stddev-deg"},
                                      std::pair<double, const char*>{heading_stddev_deg, "--heading-stddev-deg"}}) {
    if (!(value >= 0.0 && value <= kMaxAttitudeStddevDeg)) {
      throw std::invalid_argument(std::string(option) + " must be in (0, " +
                                  std::to_string(static_cast<int>(kMaxAttitudeStddevDeg)) +
                                  "] degrees (leave it out for the attitude source's)");
    }
  }
}

// Photos stored turned against the flight (stored_turn.h): every photo read
// once at a reduced size and registered with the one before it. The turned
// ones are named in a warning and in the summary; a photo the images could
// not link is counted as unchecked.
std::vector<StoredTurn> find_stored_turns(const std::vector<Sample>& samples, const std::array<double, 3>& mount,
                                          ImportSummary* summary) {
  const StoredTurnOptions options;
  StoredTurnCheck check(options);
  const Eigen::Matrix3d body_from_cam = body_from_camera(mount);
  for (const Sample& s : samples) {
    check.add(read_grey_reduced(s.image_path, options.max_side_px, s.photo.image_width, s.photo.image_height),
              s.world_from_body * body_from_cam);
  }
  std::vector<StoredTurn> turns = check.verdicts();
  std::string named;
  for (size_t i = 0; i < samples.size(); ++i) {
    if (!turns[i].linked) ++summary->orientation_unchecked;
    if (turns[i].quarter_turns == 0) continue;
    const std::string file = fs::path(samples[i].image_path).filename().string();
    summary->turned_back.push_back({samples[i].image_path, 90 * turns[i].quarter_turns});
    if (summary->turned_back.size() <= 6) named += (named.empty() ? "" : ", ") + file + " " +
                                                   std::to_string(90 * turns[i].quarter_turns) + " deg";
  }
  if (!summary->turned_back.empty()) {
    if (summary->turned_back.size() > 6) named += ", ...";
    summary->warnings.push_back(std::to_string(summary->turned_back.size()) +
                                " photos were stored turned against the rest of the flight (found from the images; "
                                "their stored turn, clockwise) and are turned back: " + named);
  }
  return turns;
}

ImportSummary run_import(const ImportOptions& o) {
  o.Check();
  ImportSummary summary;
  summary.mode = o.photos_dir.empty() ? "video" : "photos";
  summary.log_path = o.out + ".lcmlog";
  summary.yaml_path = o.out + ".yaml";

  CameraIntrinsics file_camera;
  if (!o.camera_file.empty()) file_camera = read_camera_file(o.camera_file);
  // DJI, video and the contract's photos: top of the image = forward; senseFly: established from data.
  std::array<double, 3> mount = file_camera.has_mount ? file_camera.mount_rpy_deg : kTopForwardMount;
  summary.mount_rpy_deg = mount;

  // 1. Metadata of every frame, in order, checked.
  std::vector<Sample> samples;
  std::string attitude_source;
  auto accept = [&](Sample s, const std::string& att) {
    if (!samples.empty() && !(s.time_s > samples.back().time_s)) {
      char text[160];
      std::snprintf(text, sizeof(text), "time %.3f s is not after the previous frame's %.3f s (%s)", s.time_s,
                    samples.back().time_s, samples.back().where.c_str());
      skip_or_throw(o.skip_bad, s.where, text, &summary.skipped);
      return;
    }
    if (!samples.empty() && s.height_kind != samples.front().height_kind) {
      skip_or_throw(o.skip_bad, s.where, "altimeter source " + s.height_kind + " differs from the flight's " +
                                             samples.front().height_kind, &summary.skipped);
      return;
    }
    if (!attitude_source.empty() && att != attitude_source) {
      summary.warnings.push_back(s.where + ": attitude from " + att + " where earlier frames used " + attitude_source);
    }
    attitude_source = att;
    samples.push_back(std::move(s));
  };
  Telemetry telemetry;
  if (!o.photos_dir.empty()) {
    if (!fs::is_directory(o.photos_dir)) throw std::runtime_error(o.photos_dir + ": not a folder");
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(o.photos_dir)) {
      if (e.is_regular_file() && is_image_file(e.path())) files.push_back(e.path());
    }
    std::sort(files.begin(), files.end());
    if (files.empty()) throw std::runtime_error(o.photos_dir + ": no JPEG/PNG/TIFF files");
    int64_t index = 0;
    // Every file's metadata first: the flight's camera is the one most photos
    // were taken with (model and size; on a tie the earliest), so one odd
    // photo (even the first) is what differs. Errors stay in file order.
    std::vector<PhotoMetadata> metadata(files.size());
    std::vector<std::string> read_error(files.size());
    for (size_t i = 0; i < files.size(); ++i) {
      try {
        metadata[i] = read_photo_metadata(files[i].string());
      } catch (const std::runtime_error& e) {
        read_error[i] = e.what();
      }
    }
    const FlightCamera flight_camera = most_common_camera(metadata, read_error);
    for (size_t i = 0; i < files.size(); ++i) {
      const fs::path& f = files[i];
      Sample s;
      std::string att, why;
      if (!read_error[i].empty()) {
        if (!o.skip_bad) throw std::runtime_error(read_error[i]);
        summary.skipped.push_back({f.string(), read_error[i]});
        continue;
      }
      const PhotoMetadata& m = metadata[i];
      if (samples.empty() && !file_camera.has_mount && m.has_sensefly_attitude && !m.has_dji_gimbal && !m.has_dji_flight) {
        mount = kSenseflyMount;
      }
      if (!photo_sample(m, o, mount, &s, &att, &why)) {
        skip_or_throw(o.skip_bad, f.string(), why, &summary.skipped);
        continue;
      }
      if (!same_camera(flight_camera, m, &why)) {
        skip_or_throw(o.skip_bad, f.string(), why, &summary.skipped);
        continue;
      }
      if (o.interval_s > 0.0) s.time_s = kDefaultEpochS + o.interval_s * static_cast<double>(index);
      ++index;
      accept(std::move(s), att);
    }
  } else {
    telemetry = o.srt.empty() ? read_csv(o.csv, o.skip_bad) : read_srt(o.srt, o.skip_bad);
    summary.skipped = telemetry.skipped;
    cv::VideoCapture probe(o.video);
    if (!probe.isOpened()) throw std::runtime_error(o.video + ": cannot open video");
    const double fps = probe.get(cv::CAP_PROP_FPS);
    if (!(fps > 0.0) && o.srt.empty()) throw std::runtime_error(o.video + ": no frame rate (needed to place CSV times)");
    double base = kDefaultEpochS;
    if (!telemetry.records.empty() && telemetry.records.front().absolute_time_s >= 0.0) {
      base = telemetry.records.front().absolute_time_s - telemetry.records.front().time_s;
    }
    for (size_t i = 0; i < telemetry.records.size(); ++i) {
      const TelemetryRecord& r = telemetry.records[i];
      Sample s;
      std::string att;
      s.video_frame = r.frame >= 1 ? r.frame - 1 : (o.srt.empty() ? std::llround(r.time_s * fps) : static_cast<int64_t>(i));
      s.where = o.video + " frame " + std::to_string(s.video_frame) + " (" + telemetry.path + ":" + std::to_string(r.line) + ")";
      s.time_s = base + r.time_s;
      if (!telemetry_sample(r, mount, &s, &att)) {
        skip_or_throw(o.skip_bad, telemetry.path + ":" + std::to_string(r.line), "no attitude", &summary.skipped);
        continue;
      }
      if (!samples.empty() && s.video_frame <= samples.back().video_frame) {
        skip_or_throw(o.skip_bad, s.where, "frame number not after the previous record's", &summary.skipped);
        continue;
      }
      accept(std::move(s), att);
    }
  }
  if (samples.empty()) throw std::runtime_error("no usable frames (" + std::to_string(summary.skipped.size()) + " skipped)");
  summary.attitude_source = attitude_source;
  summary.attitude_accuracy = attitude_accuracy(attitude_source, o.attitude_stddev_deg, o.heading_stddev_deg);
  summary.altimeter_source = samples.front().height_kind;
  bool all_alt = true;
  for (const Sample& s : samples) all_alt = all_alt && s.has_alt;
  // Truth altitude: the relative height when the altimeter is barometric (one
  // smooth source), the GPS altitude when the altimeter is a rangefinder.
  // Origin: the first frame written (set below; a frame skipped for its image is no origin).
  const bool truth_from_alt = summary.altimeter_source == "rangefinder" && all_alt;
  std::optional<LocalFrame> origin;
  if (summary.altimeter_source == "rangefinder" && !all_alt) {
    summary.warnings.push_back("rangefinder flight without GPS altitude in every record: truth down uses the range");
  }

  // 2. Photos stored turned against the flight (a viewer re-saved them
  // rotated), found from the images: turned back as they are read below.
  std::vector<StoredTurn> turns;
  if (!o.photos_dir.empty()) turns = find_stored_turns(samples, mount, &summary);

  // 3. Images: read, check size, grey, scale; write the log body.
  const fs::path out_dir = fs::path(o.out).parent_path();
  if (!out_dir.empty()) fs::create_directories(out_dir);
  const std::string body_path = summary.log_path + ".part";
  std::unique_ptr<cv::VideoCapture> video;
  int64_t video_position = 0;
  if (!o.video.empty()) video = std::make_unique<cv::VideoCapture>(o.video);
  bool camera_known = !o.camera_file.empty();
  CameraIntrinsics source_camera = file_camera;  // at the size of the files
  std::vector<Sample> written;
  std::vector<size_t> written_index;  // ... and where each is in `samples`
  {
    LogWriter body(body_path);
    ProgressBar progress("import", static_cast<double>(samples.size()), o.progress);
    for (size_t i = 0; i < samples.size(); ++i) {
      progress.update(static_cast<double>(i));
      const Sample& s = samples[i];
      cv::Mat frame;
      if (video) {
        cv::Mat colour;
        while (video_position <= s.video_frame && video->read(colour)) ++video_position;
        if (video_position <= s.video_frame || colour.empty()) {
          skip_or_throw(o.skip_bad, s.where, "the video has no such frame (it ends at frame " +
                                                 std::to_string(video_position) + ")", &summary.skipped);
          continue;
        }
        if (colour.channels() == 3) {
          cv::cvtColor(colour, frame, cv::COLOR_BGR2GRAY);
        } else {
          frame = colour;
        }
      } else {
        // The pixels as stored: EXIF Orientation is a display hint; the stored
        // turn check above decides from the images what is turned.
        frame = cv::imread(s.image_path, cv::IMREAD_GRAYSCALE | cv::IMREAD_IGNORE_ORIENTATION);
        if (frame.empty()) {
          skip_or_throw(o.skip_bad, s.where, "cannot decode the image", &summary.skipped);
          continue;
        }
        const StoredTurn& turn = turns[i];
        if (turn.size_transposed && !turn.linked) {
          skip_or_throw(o.skip_bad, s.where,
                        "stored turned by a quarter turn (its width and height are the flight's swapped) and no "
                        "neighbouring photo matched it to tell which way: turn it back, or leave it out (--skip-bad)",
                        &summary.skipped);
          continue;
        }
        frame = turn_back(frame, turn.quarter_turns);
      }
      if (frame.depth() != CV_8U) frame.convertTo(frame, CV_8U, 1.0 / 256.0);
      if (!camera_known) {
        if (o.focal_px > 0.0) {
          source_camera = camera_from_focal(o.focal_px, frame.cols, frame.rows, "--focal-px");
        } else if (!o.photos_dir.empty()) {
          const PhotoFocal f = focal_from_photo(s.photo, frame.cols, frame.rows);
          source_camera = camera_from_focal(f.focal_px, frame.cols, frame.rows, f.source);
          if (f.has_center) source_camera.cx = f.cx, source_camera.cy = f.cy;
          if (f.fy > 0.0) source_camera.fy = f.fy;
          if (!f.distortion.empty()) source_camera.distortion = f.distortion;
          summary.camera_model = s.photo.model;
          summary.focal_rule = f.rule;
          summary.warnings.push_back(f.warning);
        } else {
          throw std::runtime_error(s.where + ": no camera: give --camera FILE or --focal-px (a video has no focal length)");
        }
        camera_known = true;
      }
      // The first written frame's size sets the working resolution (--scale, else the rule).
      const WorkingResolution resolution =
          summary.resolution.width > 0 ? summary.resolution : working_resolution(frame.cols, frame.rows, o.scale);
      const double scale = resolution.scale;
      // The calibration describes the files as they are (scaled here) or the
      // output (already at the working size).
      if (frame.cols == source_camera.width && frame.rows == source_camera.height) {
        summary.camera = source_camera.scaled(scale);
      } else if (scale < 1.0 && std::lround(frame.cols * scale) == source_camera.width &&
                 std::lround(frame.rows * scale) == source_camera.height) {
        summary.camera = source_camera;
      } else {
        char text[240];
        std::snprintf(text, sizeof(text), "frame is %dx%d but the camera (%s) is %dx%d%s", frame.cols, frame.rows,
                      source_camera.source.c_str(), source_camera.width, source_camera.height,
                      scale < 1.0 ? " (neither the files' size nor the working size)" : "");
        std::string why = text;
        // A calibration of the images shrunk uniformly: say which --scale it is for.
        const double ratio = static_cast<double>(source_camera.width) / frame.cols;
        if (ratio < 1.0 && std::lround(frame.rows * ratio) == source_camera.height) {
          std::snprintf(text, sizeof(text), "; give --scale %.6g for a calibration at that size", ratio);
          why += text;
        }
        skip_or_throw(o.skip_bad, s.where, why, &summary.skipped);
        continue;
      }
      summary.resolution = resolution;
      if (frame.cols != summary.camera.width || frame.rows != summary.camera.height) {
        cv::Mat small;
        cv::resize(frame, small, cv::Size(summary.camera.width, summary.camera.height), 0, 0, cv::INTER_AREA);
        frame = small;
      }
      if (!frame.isContinuous()) frame = frame.clone();

      if (!origin) origin.emplace(samples, i, truth_from_alt);
      const LocalFrame& local = *origin;
      const int64_t t = std::llround(s.time_s * 1e6);
      const Eigen::Vector3d rpy = rpy_from_rotation(s.world_from_body);
      const Eigen::Vector3d p = local.ned(i);
      ins_t ins{};
      ins.device_utime = t;
      ins.roll = rpy.x();
      ins.pitch = rpy.y();
      ins.yaw = rpy.z();
      ins.has_rates = false;
      ins.latitude_deg = s.lat_deg;
      ins.longitude_deg = s.lon_deg;
      ins.height_m = s.has_alt ? s.alt_m : s.height_m;
      ins.ins_status = 3;
      ins.flags = ins_t::FLAG_ALIGNED | ins_t::FLAG_SOLUTION_GOOD;
      ins.has_stddev = false;
      ins.utime = t - 1000;
      write_message(&body, ins.utime, channels::kIns, ins);

      altimeter_t alt{};
      alt.utime = t - 1000;
      alt.range_m = s.height_m;
      const Eigen::Vector3d down_in_body = s.world_from_body.transpose() * Eigen::Vector3d::UnitZ();
      for (int k = 0; k < 3; ++k) alt.beam_body[k] = down_in_body[k];
      alt.signal_quality = -1.f;
      alt.validity = altimeter_t::VALID_OK;
      write_message(&body, alt.utime, channels::kAltimeter, alt);

      image_t img{};
      img.utime = t;
      img.trigger_utime = t;
      img.frame_counter = static_cast<int64_t>(i);
      img.trigger_sequence = -1;
      img.width = frame.cols;
      img.height = frame.rows;
      img.stride = frame.cols;
      img.pixel_format = image_t::PIXEL_MONO8;
      img.time_quality = image_t::TIME_CAMERA_CLOCK;
      img.size = frame.cols * frame.rows;
      img.data.assign(frame.data, frame.data + img.size);
      write_message(&body, t, channels::kCameraImage, img);

      ground_truth_t gt{};
      gt.utime = t;
      gt.kind = ground_truth_t::KIND_FRAME;
      for (int k = 0; k < 3; ++k) gt.position_ned[k] = p[k];
      gt.roll = rpy.x();
      gt.pitch = rpy.y();
      gt.yaw = rpy.z();
      gt.height_agl_m = s.height_m;
      gt.terrain_height_m = -p.z() - s.height_m;
      // velocity: finite difference with the neighbours in the metadata list
      const size_t a = i > 0 ? i - 1 : i, b = i + 1 < samples.size() ? i + 1 : i;
      if (b > a) {
        const Eigen::Vector3d v = (local.ned(b) - local.ned(a)) / (samples[b].time_s - samples[a].time_s);
        for (int k = 0; k < 3; ++k) gt.velocity_ned[k] = ins.velocity_ned[k] = v[k];
      }
      write_message(&body, t, channels::kGroundTruth, gt);
      ins.utime = t + 1000;
      write_message(&body, ins.utime, channels::kIns, ins);
      written.push_back(s);
      written_index.push_back(i);
    }
    progress.finish();
    body.flush();
  }
  if (written.empty()) {
    fs::remove(body_path);
    throw std::runtime_error("no frame written (" + std::to_string(summary.skipped.size()) + " skipped)");
  }
  summary.frames_written = static_cast<int64_t>(written.size());
  summary.first_time_s = written.front().time_s;
  summary.last_time_s = written.back().time_s;
  std::vector<double> intervals;
  for (size_t i = 1; i < written.size(); ++i) {
    intervals.push_back(written[i].time_s - written[i - 1].time_s);
    summary.max_gap_s = std::max(summary.max_gap_s, intervals.back());
    summary.distance_m += (origin->ned(written_index[i]) - origin->ned(written_index[i - 1])).norm();
  }
  summary.median_interval_s = intervals.empty() ? 0.0 : median(intervals, EvenMedian::kUpper);
  summary.mount_rpy_deg = mount;

  // 4. The final log: CONFIG first, then the body; and the config file.
  {
    LogWriter log(summary.log_path);
    config_t cfg;
    cfg.utime = std::llround(summary.first_time_s * 1e6) - 2000;
    cfg.name = "import";
    cfg.source = o.photos_dir.empty() ? o.video : o.photos_dir;
    cfg.yaml = config_message_yaml(o, summary);
    write_message(&log, cfg.utime, channels::kConfig, cfg);
    LogReader reader(body_path);
    LogEvent e;
    while (reader.next(&e)) log.write(e.timestamp, e.channel, e.data, e.size);
    log.flush();
  }
  fs::remove(body_path);
  std::ofstream yaml(summary.yaml_path);
  yaml << output_yaml(o, summary);
  if (!yaml) throw std::runtime_error(summary.yaml_path + ": cannot write");
  return summary;
}

std::string summary_json(const ImportSummary& s) {
  JsonWriter j;
  j.begin_object()
      .field("log", s.log_path)
      .field("config", s.yaml_path)
      .field("mode", s.mode)
      .field("frames_written", s.frames_written)
      .field("skipped_count", static_cast<int64_t>(s.skipped.size()));
  j.key("skipped").begin_array();
  for (const SkippedInput& k : s.skipped) j.begin_object().field("where", k.where).field("reason", k.reason).end_object();
  j.end_array();
  j.field("first_time_s", s.first_time_s)
      .field("last_time_s", s.last_time_s)
      .field("time_span_s", s.last_time_s - s.first_time_s)
      .field("median_interval_s", s.median_interval_s)
      .field("max_gap_s", s.max_gap_s)
      .field("distance_m", s.distance_m)
      .field("altimeter_source", s.altimeter_source)
      .field("attitude_source", s.attitude_source);
  j.key("attitude_accuracy")
      .begin_object()
      .field("roll_pitch_stddev_deg", s.attitude_accuracy.roll_pitch_stddev_deg)
      .field("heading_stddev_deg", s.attitude_accuracy.heading_stddev_deg)
      .field("from_base_config", s.attitude_accuracy.from_base_config)
      .field("basis", s.attitude_accuracy.basis)
      .end_object();
  j.key("turned_back").begin_array();
  for (const TurnedPhoto& t : s.turned_back) j.begin_object().field("where", t.where).field("degrees", t.degrees).end_object();
  j.end_array();
  j.field("orientation_unchecked", s.orientation_unchecked);
  j.key("camera")
      .begin_object()
      .field("source", s.camera.source)
      .field("model", s.camera_model)
      .field("focal_rule", s.focal_rule)
      .field("width", s.camera.width)
      .field("height", s.camera.height)
      .field("scale", s.resolution.scale)
      .field("scale_rule", s.resolution.rule)
      .field("fx", s.camera.fx)
      .field("fy", s.camera.fy)
      .field("cx", s.camera.cx)
      .field("cy", s.camera.cy);
  j.key("mount_rpy_deg").begin_array();
  for (double v : s.mount_rpy_deg) j.value(v);
  j.end_array().end_object();
  j.key("warnings").begin_array();
  for (const std::string& w : s.warnings) j.value(w);
  j.end_array().end_object();
  return j.str();
}

std::string summary_text(const ImportSummary& s) {
  char text[512];
  std::snprintf(text, sizeof(text),
                "nadir_import: %lld frames (%s) -> %s + %s; %zu skipped; %.1f s, %.0f m along GPS; camera %dx%d fx %.1f "
                "fy %.1f (%s); attitude %s; altimeter %s\n",
                static_cast<long long>(s.frames_written), s.mode.c_str(), s.log_path.c_str(), s.yaml_path.c_str(),
                s.skipped.size(), s.last_time_s - s.first_time_s, s.distance_m, s.camera.width, s.camera.height,
                s.camera.fx, s.camera.fy, s.camera.source.c_str(), s.attitude_source.c_str(),
                s.altimeter_source.c_str());
  std::string out = text;
  out += "  " + describe(s.resolution) + "\n";
  out += "  attitude accuracy: " + describe(s.attitude_accuracy) + "\n";
  if (!s.focal_rule.empty()) out += "  focal length: " + s.focal_rule + "\n";
  for (const SkippedInput& k : s.skipped) out += "  skipped " + k.where + ": " + k.reason + "\n";
  for (const std::string& w : s.warnings) out += "  warning: " + w + "\n";
  return out;
}

}  // namespace nadir::import
