#include "tools/export/exporter.h"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include <cmath>
#include <optional>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "common/geometry.h"
#include "common/ground_footprint.h"
#include "common/progress.h"

namespace fs = std::filesystem;

namespace nadir::exporter {
namespace {

void require(bool ok, const std::string& option, const std::string& what) {
  if (!ok) throw std::invalid_argument(option + " " + what);
}

// The attitude written for a frame: body (flight) and camera (gimbal) angles.
struct FrameAttitude {
  DjiAngles flight;
  DjiAngles gimbal;
  Eigen::Matrix3d world_from_body;
};

FrameAttitude frame_attitude(const SimLog& log, const CameraModel& turned, const ground_truth_t& truth,
                             AttitudeSource source) {
  double roll = truth.roll, pitch = truth.pitch, yaw = truth.yaw;
  if (source == AttitudeSource::kIns) {
    const ins_t& ins = log.ins()[log.nearest_ins(truth.utime)];
    roll = ins.roll;
    pitch = ins.pitch;
    yaw = ins.yaw;
  }
  FrameAttitude a;
  a.world_from_body = rotation_from_rpy(roll, pitch, yaw);
  a.flight = {rad_to_deg(roll), rad_to_deg(pitch), rad_to_deg(yaw)};
  a.gimbal = gimbal_angles(a.world_from_body * turned.body_from_camera, yaw);
  return a;
}

// Metadata of the frame stamped `image_utime` (truth at its true exposure),
// for a photo of camera `written` whose sensor's full frame has a diagonal of
// `sensor_diagonal_px` pixels (the photo's own diagonal unless it is a crop).
PhotoMetadata frame_metadata(const SimLog& log, const CameraModel& written, int64_t image_utime,
                             AttitudeSource source, double pixel_pitch_um, double sensor_diagonal_px) {
  const ground_truth_t& truth = log.truth_for_frame(image_utime);
  PhotoMetadata m;
  m.utime = image_utime;
  m.width = written.width;
  m.height = written.height;
  m.pixel_pitch_um = pixel_pitch_um;
  m.focal_length_mm = written.fx * pixel_pitch_um * 1e-3;
  // 35 mm equivalent by the full frame's diagonal (43.27 mm), as cameras write it.
  m.focal_length_35mm = written.fx * 43.27 / sensor_diagonal_px;
  log.ins_position_at(truth.utime, &m.latitude_deg, &m.longitude_deg, &m.altitude_m);
  const FrameAttitude a = frame_attitude(log, written, truth, source);
  m.flight = a.flight;
  m.gimbal = a.gimbal;
  m.relative_altitude_m = -truth.position_ned[2];  // the take-off point is the NED origin's ground
  m.absolute_altitude_m = m.altitude_m;
  return m;
}

// The rows of a 16:9 crop (full width, centre rows) of an image `width` x `height`.
cv::Rect crop_16_9_rows(int width, int height) {
  const int rows = static_cast<int>(std::lround(width * 9.0 / 16.0));
  if (rows > height) {
    throw std::invalid_argument("--crop-16-9: the " + std::to_string(width) + "x" + std::to_string(height) +
                                " image is not tall enough for a 16:9 crop of its width");
  }
  return cv::Rect(0, (height - rows) / 2, width, rows);
}

cv::Mat sim_frame(const SimLog& log, const SimImageRef& ref) {
  const image_t image = log.decode_image(ref);
  return cv::Mat(image.height, image.width, CV_8UC1, const_cast<uint8_t*>(image.data.data()),
                 static_cast<size_t>(image.stride))
      .clone();
}

std::string attitude_name(AttitudeSource s) { return s == AttitudeSource::kTruth ? "truth" : "ins"; }

}  // namespace

AttitudeSource parse_attitude_source(const std::string& name) {
  if (name == "truth") return AttitudeSource::kTruth;
  if (name == "ins") return AttitudeSource::kIns;
  throw std::invalid_argument("--attitude '" + name + "' must be truth or ins");
}

void PhotoExportOptions::Check() const {
  require(interval_s >= 0.05 && interval_s <= 3600.0, "--interval", "must be in [0.05, 3600] s");
  require(max_yaw_rate_dps > 0.0 && max_yaw_rate_dps <= 360.0, "--max-yaw-rate-dps", "must be in (0, 360]");
  require(quality >= 1 && quality <= 100, "--quality", "must be in [1, 100]");
  require(pixel_pitch_um >= 0.5 && pixel_pitch_um <= 50.0, "--pixel-pitch-um", "must be in [0.5, 50]");
  require(model.find_first_of("\r\n") == std::string::npos, "--model", "must be one line");
  require(return_lines_turn_deg % 90 == 0 && return_lines_turn_deg >= 0 && return_lines_turn_deg < 360,
          "--turn-return-lines", "must be 0, 90, 180 or 270");
  require(std::fabs(yaw_offset_deg) <= 180.0, "--yaw-offset-deg", "must be in [-180, 180]");
}

void VideoExportOptions::Check() const {
  require(every >= 1 && every <= 10000, "--every", "must be in [1, 10000]");
  require(max_range_age_s > 0.0 && max_range_age_s <= 10.0, "--max-range-age", "must be in (0, 10] s");
}

void write_calibration(const CameraModel& camera, const std::string& path) {
  cv::FileStorage file(path, cv::FileStorage::WRITE);
  if (!file.isOpened()) throw std::runtime_error(path + ": cannot write the camera calibration");
  std::vector<double> d = camera.distortion;
  d.resize(5, 0.0);
  file << "camera_matrix" << cv::Mat(camera.camera_matrix());
  file << "distortion_coefficients" << cv::Mat(d, true).reshape(1, 1);
  file << "image_width" << camera.width;
  file << "image_height" << camera.height;
  const Eigen::Vector3d mount = rpy_from_rotation(camera.body_from_camera);
  file << "mount_rpy_deg" << std::vector<double>{rad_to_deg(mount[0]), rad_to_deg(mount[1]), rad_to_deg(mount[2])};
  file.release();
}

namespace {

// DJI's DewarpData for `camera`: the principal point as an offset from the
// centre of the pixel grid ((W - 1) / 2, (H - 1) / 2), then k1 k2 p1 p2 k3.
std::string dewarp_data_text(const CameraModel& camera) {
  std::vector<double> d = camera.distortion;
  d.resize(5, 0.0);
  char text[400];
  std::snprintf(text, sizeof(text), "2026-01-01;%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g", camera.fx,
                camera.fy, camera.cx - 0.5 * (camera.width - 1), camera.cy - 0.5 * (camera.height - 1), d[0], d[1], d[2],
                d[3], d[4]);
  return text;
}

}  // namespace

PhotoExportResult export_photos(const SimLog& log, const std::string& out_dir, const PhotoExportOptions& options) {
  options.Check();
  std::error_code ec;
  fs::create_directories(out_dir, ec);
  if (ec) throw std::runtime_error(out_dir + ": cannot create the folder: " + ec.message());
  const CameraModel turned = turned_camera(log.camera());
  PhotoExportResult result;
  result.attitude_source = attitude_name(options.attitude);
  result.camera_file = (fs::path(out_dir) / "camera.yaml").string();
  // The written photo: the turned image, or its 16:9 crop; the sensor's full
  // frame: the turned image, or the 4:3 frame of the crop's width.
  CameraModel written = turned;
  cv::Rect crop(0, 0, turned.width, turned.height);
  double sensor_diagonal_px = std::hypot(turned.width, turned.height);
  if (options.crop_16_9) {
    crop = crop_16_9_rows(turned.width, turned.height);
    written.height = crop.height;
    written.cy -= crop.y;
    sensor_diagonal_px = std::hypot(turned.width, turned.width * 3.0 / 4.0);
  }
  result.camera = written;
  write_calibration(written, result.camera_file);

  const std::vector<SimImageRef>& images = log.images();
  const int64_t t0 = images.front().utime, t_end = images.back().utime;
  const int64_t step = static_cast<int64_t>(std::llround(options.interval_s * 1e6));
  const int64_t frame_us = static_cast<int64_t>(1e6 / log.camera().rate_hz);
  ProgressBar progress("export photos", static_cast<double>(t_end - t0), options.progress);
  size_t next_image = 0;
  const ground_truth_t* previous_truth = nullptr;
  std::vector<Eigen::Vector2d> previous_footprint;
  std::optional<double> first_yaw_rad;  // the first photo's heading: the return lines are the others
  for (int64_t tick = t0; tick <= t_end; tick += step) {
    progress.update(static_cast<double>(tick - t0));
    if (std::fabs(rad_to_deg(log.yaw_rate_at(tick))) > options.max_yaw_rate_dps) {
      ++result.skipped_in_turns;
      continue;
    }
    // The frame nearest the tick (a dropped frame leaves the tick without a photo).
    while (next_image + 1 < images.size() &&
           std::llabs(images[next_image + 1].utime - tick) <= std::llabs(images[next_image].utime - tick)) {
      ++next_image;
    }
    const SimImageRef& ref = images[next_image];
    if (std::llabs(ref.utime - tick) > frame_us / 2 + 1) {
      ++result.ticks_without_image;
      continue;
    }
    PhotoRecord record;
    char name[32];
    std::snprintf(name, sizeof(name), "DJI_%04d.JPG", static_cast<int>(result.photos.size()) + 1);
    record.file = name;
    record.utime = ref.utime;
    record.metadata =
        frame_metadata(log, written, ref.utime, options.attitude, options.pixel_pitch_um, sensor_diagonal_px);
    if (!options.model.empty()) record.metadata.model = options.model;
    if (options.dji_dewarp) record.metadata.dewarp_data = dewarp_data_text(written);
    record.metadata.flight.yaw_deg += options.yaw_offset_deg;
    record.metadata.gimbal.yaw_deg += options.yaw_offset_deg;
    if (options.dji_calibration) {
      record.metadata.has_dji_calibration = true;
      record.metadata.calibrated_focal_px = written.fx;
      record.metadata.calibrated_center_x = written.cx;
      record.metadata.calibrated_center_y = written.cy;
    }
    const std::string path = (fs::path(out_dir) / name).string();
    const ground_truth_t& truth = log.truth_for_frame(ref.utime);
    if (first_yaw_rad.has_value() && std::fabs(angle_difference(truth.yaw, *first_yaw_rad)) > M_PI / 2) {
      record.stored_turn_deg = options.return_lines_turn_deg;
    }
    if (!first_yaw_rad) first_yaw_rad = truth.yaw;
    cv::Mat photo = turn_to_dji(sim_frame(log, ref))(crop);
    static constexpr int kClockwise[] = {-1, cv::ROTATE_90_CLOCKWISE, cv::ROTATE_180, cv::ROTATE_90_COUNTERCLOCKWISE};
    if (record.stored_turn_deg != 0) {
      cv::Mat turned_pixels;
      cv::rotate(photo, turned_pixels, kClockwise[record.stored_turn_deg / 90]);
      photo = turned_pixels;
      record.metadata.width = photo.cols;
      record.metadata.height = photo.rows;
    }
    if (!cv::imwrite(path, photo, {cv::IMWRITE_JPEG_QUALITY, options.quality})) {
      throw std::runtime_error(path + ": cannot write the JPEG");
    }
    write_photo_metadata(path, record.metadata);
    const std::vector<Eigen::Vector2d> footprint =
        ground_footprint(log.camera(), Eigen::Vector3d(truth.position_ned[0], truth.position_ned[1], truth.position_ned[2]),
                         rotation_from_rpy(truth.roll, truth.pitch, truth.yaw), -truth.terrain_height_m);
    if (previous_truth) {
      record.overlap_with_previous = footprint_overlap(previous_footprint, footprint);
      record.heading_change_deg = rad_to_deg(angle_difference(truth.yaw, previous_truth->yaw));
    }
    record.north_m = truth.position_ned[0];
    record.east_m = truth.position_ned[1];
    previous_truth = &truth;
    previous_footprint = footprint;
    result.photos.push_back(record);
  }
  progress.finish();
  if (result.photos.empty()) throw std::runtime_error(log.path() + ": no photo exported (every tick in a turn?)");
  return result;
}

VideoExportResult export_video(const SimLog& log, const std::string& video_path, const std::string& srt_path,
                               const std::string& csv_path, const VideoExportOptions& options) {
  options.Check();
  const CameraModel turned = turned_camera(log.camera());
  VideoExportResult result;
  result.fps = log.camera().rate_hz / options.every;
  cv::VideoWriter video(video_path, cv::CAP_OPENCV_MJPEG, cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), result.fps,
                        cv::Size(turned.width, turned.height), true);
  if (!video.isOpened()) throw std::runtime_error(video_path + ": cannot open an MJPG AVI for writing");
  std::ofstream srt(srt_path);
  if (!srt) throw std::runtime_error(srt_path + ": cannot write the SRT");
  std::ofstream csv;
  if (!csv_path.empty()) {
    csv.open(csv_path);
    if (!csv) throw std::runtime_error(csv_path + ": cannot write the CSV");
    csv << "time_s,roll_deg,pitch_deg,yaw_deg,height_m,lat_deg,lon_deg,alt_m\n";
  }
  const std::vector<SimImageRef>& images = log.images();
  ProgressBar progress("export video", static_cast<double>(images.size()), options.progress);
  const int64_t max_range_age_us = static_cast<int64_t>(options.max_range_age_s * 1e6);
  int64_t previous = 0;
  char line[512];
  for (size_t i = 0; i < images.size(); i += static_cast<size_t>(options.every)) {
    progress.update(static_cast<double>(i));
    const SimImageRef& ref = images[i];
    // OpenCV 4.6's own MJPEG encoder writes broken single-channel frames:
    // grey goes in as three equal channels.
    cv::Mat frame;
    cv::cvtColor(turn_to_dji(sim_frame(log, ref)), frame, cv::COLOR_GRAY2BGR);
    video.write(frame);
    const PhotoMetadata m = frame_metadata(log, turned, ref.utime, options.attitude, 0.0, std::hypot(turned.width, turned.height));
    if (result.frames == 0) result.first_utime = ref.utime;
    const int64_t from_ms = (ref.utime - result.first_utime + 500) / 1000;
    const int64_t diff_ms = result.frames == 0 ? std::llround(1000.0 / result.fps) : (ref.utime - previous + 500) / 1000;
    const int64_t to_ms = from_ms + std::llround(1000.0 / result.fps);
    ++result.frames;
    auto clock = [](int64_t ms) {
      char text[32];
      std::snprintf(text, sizeof(text), "%02lld:%02lld:%02lld,%03lld", static_cast<long long>(ms / 3600000),
                    static_cast<long long>(ms / 60000 % 60), static_cast<long long>(ms / 1000 % 60),
                    static_cast<long long>(ms % 1000));
      return std::string(text);
    };
    srt << result.frames << "\n" << clock(from_ms) << " --> " << clock(to_ms) << "\n";
    srt << "FrameCnt: " << result.frames << ", DiffTime: " << diff_ms << "ms\n" << srt_date_time(ref.utime) << "\n";
    std::snprintf(line, sizeof(line),
                  "[latitude: %.8f] [longitude: %.8f] [rel_alt: %.3f abs_alt: %.3f] "
                  "[gb_yaw: %.6f gb_pitch: %.6f gb_roll: %.6f] [flight_yaw: %.6f flight_pitch: %.6f flight_roll: %.6f]",
                  m.latitude_deg, m.longitude_deg, m.relative_altitude_m, m.absolute_altitude_m, m.gimbal.yaw_deg,
                  m.gimbal.pitch_deg, m.gimbal.roll_deg, m.flight.yaw_deg, m.flight.pitch_deg, m.flight.roll_deg);
    srt << line;
    double range = 0.0;
    if (options.range) {
      // A telemetry stream either has ranges or has not: a frame without one is an error.
      if (!log.range_near(ref.utime, max_range_age_us, &range)) {
        throw std::runtime_error(log.path() + ": no valid altimeter range within " +
                                 std::to_string(options.max_range_age_s) + " s of the frame at utime " +
                                 std::to_string(ref.utime) + " (use --no-range)");
      }
      std::snprintf(line, sizeof(line), " [range: %.3f]", range);
      srt << line;
      ++result.frames_with_range;
    }
    srt << "\n\n";
    if (csv.is_open()) {
      std::snprintf(line, sizeof(line), "%.6f,%.6f,%.6f,%.6f,%.3f,%.8f,%.8f,%.3f\n",
                    (ref.utime - result.first_utime) * 1e-6, m.flight.roll_deg, m.flight.pitch_deg, m.flight.yaw_deg,
                    m.relative_altitude_m, m.latitude_deg, m.longitude_deg, m.altitude_m);
      csv << line;
    }
    previous = ref.utime;
    result.last_utime = ref.utime;
  }
  progress.finish();
  video.release();
  if (!srt.good()) throw std::runtime_error(srt_path + ": write failed");
  if (csv.is_open() && !csv.good()) throw std::runtime_error(csv_path + ": write failed");
  return result;
}

}  // namespace nadir::exporter
