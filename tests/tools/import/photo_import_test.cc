// nadir_import end to end on inputs made here: JPEGs written with OpenCV and
// tagged through exiv2 (DJI and senseFly XMP), an MJPG video with an SRT / CSV.
// The log is read back and every message checked; bad inputs fail naming the
// file (or are skipped and counted with skip_bad).
#include <gtest/gtest.h>

#include <exiv2/exiv2.hpp>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "common/channels.h"
#include "common/config.h"
#include "common/geometry.h"
#include "common/log_file.h"
#include "common/message_guard.h"
#include "nadir/altimeter_t.hpp"
#include "nadir/config_t.hpp"
#include "nadir/ground_truth_t.hpp"
#include "nadir/image_t.hpp"
#include "nadir/ins_t.hpp"
#include "tests/common/test_support.h"
#include "tools/import/attitude_accuracy.h"
#include "tools/import/camera_table.h"
#include "tools/import/flight_import.h"
#include "tools/import/photo_camera.h"

namespace nadir::import {
namespace {

using nadir::testing::TempDir;

struct PhotoTags {
  std::string time = "2024:05:01 10:00:00";
  std::string subsec = "250";
  double lat = 47.5, lon = 8.25;
  bool dji = true;          // DJI gimbal + relative altitude; false: senseFly
  bool attitude = true;
  double yaw = 0, pitch = -90, roll = 0;  // DJI gimbal or senseFly heading/pitch/roll
  double height = 40.0;
};

cv::Mat texture(int w, int h, int seed) {
  cv::Mat m(h, w, CV_8UC3);
  cv::RNG rng(static_cast<uint64_t>(seed));
  rng.fill(m, cv::RNG::UNIFORM, 0, 255);
  return m;
}

std::string rational(double deg) {
  const double d = std::floor(deg), m = std::floor((deg - d) * 60.0), s = ((deg - d) * 60.0 - m) * 60.0;
  return std::to_string(static_cast<int>(d)) + "/1 " + std::to_string(static_cast<int>(m)) + "/1 " +
         std::to_string(static_cast<long>(std::llround(s * 10000))) + "/10000";
}

// Writes the EXIF / XMP of `t` into the image file at `path`.
void tag_photo(const std::string& path, const PhotoTags& t) {
  register_vendor_namespaces();
  auto image = Exiv2::ImageFactory::open(path);
  image->readMetadata();
  Exiv2::ExifData& exif = image->exifData();
  if (!t.time.empty()) exif["Exif.Photo.DateTimeOriginal"] = t.time;
  if (!t.subsec.empty()) exif["Exif.Photo.SubSecTimeOriginal"] = t.subsec;
  exif["Exif.GPSInfo.GPSLatitude"] = rational(std::abs(t.lat));
  exif["Exif.GPSInfo.GPSLatitudeRef"] = t.lat >= 0 ? "N" : "S";
  exif["Exif.GPSInfo.GPSLongitude"] = rational(std::abs(t.lon));
  exif["Exif.GPSInfo.GPSLongitudeRef"] = t.lon >= 0 ? "E" : "W";
  Exiv2::XmpData& xmp = image->xmpData();
  if (t.dji) {
    if (t.attitude) {
      xmp["Xmp.drone-dji.GimbalRollDegree"] = std::to_string(t.roll);
      xmp["Xmp.drone-dji.GimbalPitchDegree"] = std::to_string(t.pitch);
      xmp["Xmp.drone-dji.GimbalYawDegree"] = std::to_string(t.yaw);
    }
    xmp["Xmp.drone-dji.RelativeAltitude"] = std::to_string(t.height);
  } else {
    if (t.attitude) {
      xmp["Xmp.sensefly.RollAngle"] = std::to_string(t.roll);
      xmp["Xmp.sensefly.PitchAngle"] = std::to_string(t.pitch);
      xmp["Xmp.sensefly.Heading"] = std::to_string(t.yaw);
    }
    xmp["Xmp.sensefly.Height"] = std::to_string(t.height);
  }
  image->writeMetadata();
}

void write_photo(const std::string& path, const PhotoTags& t, int w = 320, int h = 240, int seed = 1) {
  ASSERT_TRUE(cv::imwrite(path, texture(w, h, seed)));
  tag_photo(path, t);
}

void write_camera(const std::string& path, int w, int h, double f) {
  cv::FileStorage fs(path, cv::FileStorage::WRITE);
  fs << "image_width" << w << "image_height" << h;
  fs << "camera_matrix" << cv::Mat(cv::Matx33d(f, 0, (w - 1) / 2.0, 0, f, (h - 1) / 2.0, 0, 0, 1));
  fs << "distortion_coefficients" << cv::Mat(cv::Matx<double, 1, 5>(-0.1, 0.01, 0, 0, 0));
}

struct LogContents {
  std::vector<ins_t> ins;
  std::vector<altimeter_t> altimeter;
  std::vector<image_t> images;
  std::vector<ground_truth_t> truth;
  std::vector<config_t> config;
  std::vector<std::string> order;
};

LogContents read_log(const std::string& path) {
  LogContents c;
  LogReader reader(path);
  LogEvent e;
  std::string why;
  while (reader.next(&e)) {
    c.order.push_back(e.channel);
    if (e.channel == channels::kIns) {
      c.ins.emplace_back();
      EXPECT_TRUE(decode_message(e.data, e.size, &c.ins.back(), &why));
    } else if (e.channel == channels::kAltimeter) {
      c.altimeter.emplace_back();
      EXPECT_TRUE(decode_message(e.data, e.size, &c.altimeter.back(), &why));
    } else if (e.channel == channels::kCameraImage) {
      c.images.emplace_back();
      EXPECT_TRUE(decode_message(e.data, e.size, &c.images.back(), &why));
    } else if (e.channel == channels::kGroundTruth) {
      c.truth.emplace_back();
      EXPECT_TRUE(decode_message(e.data, e.size, &c.truth.back(), &why));
    } else if (e.channel == channels::kConfig) {
      c.config.emplace_back();
      EXPECT_TRUE(decode_message(e.data, e.size, &c.config.back(), &why));
    }
  }
  EXPECT_EQ(reader.corrupt_records(), 0);
  return c;
}

ImportOptions photo_options(const TempDir& dir) {
  ImportOptions o;
  o.photos_dir = dir.file("photos");
  o.out = dir.file("out/flight");
  o.config_path = std::string(NADIR_SOURCE_DIR) + "/config/default.yaml";
  return o;
}

std::string import_error(const ImportOptions& o) {
  try {
    run_import(o);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

// A DJI survey with a 180 deg turn: gimbal angles -> body attitude, GPS -> local NED truth,
// relative altitude -> a vertical barometric altimeter, the camera scaled by 0.5.
TEST(PhotoImport, DjiSurveyWithTurn) {
  TempDir dir("import_dji");
  std::filesystem::create_directories(dir.file("photos"));
  const double yaws[] = {0.0, 0.0, 180.0, -179.0};
  for (int i = 0; i < 4; ++i) {
    PhotoTags t;
    t.time = "2024:05:01 10:00:0" + std::to_string(2 * i);
    t.subsec = i == 1 ? "5" : "250";  // 0.5 s, not 0.005
    t.lat = 47.5 + 0.0001 * i;
    t.yaw = yaws[i];
    t.pitch = i == 3 ? -85.0 : -90.0;  // 5 deg forward tilt in the last photo
    t.height = 40.0 + i;
    write_photo(dir.file("photos/DJI_000" + std::to_string(i) + ".JPG"), t, 320, 240, i);
  }
  write_camera(dir.file("cam.yaml"), 320, 240, 300.0);
  ImportOptions o = photo_options(dir);
  o.camera_file = dir.file("cam.yaml");
  o.scale = 0.5;
  const ImportSummary s = run_import(o);
  EXPECT_EQ(s.frames_written, 4);
  EXPECT_TRUE(s.skipped.empty());
  EXPECT_EQ(s.attitude_source, "dji_gimbal");
  EXPECT_EQ(s.altimeter_source, "barometric_relative");
  EXPECT_EQ(s.camera.width, 160);
  EXPECT_DOUBLE_EQ(s.camera.fx, 150.0);
  EXPECT_DOUBLE_EQ(s.camera.cx, 79.5);
  EXPECT_NEAR(s.first_time_s, 1714557600.25, 1e-6);
  EXPECT_NEAR(s.max_gap_s, 2.25, 1e-6);

  const LogContents log = read_log(s.log_path);
  ASSERT_EQ(log.config.size(), 1u);
  EXPECT_EQ(log.order.front(), channels::kConfig);
  EXPECT_NE(log.config[0].yaml.find("altimeter_source: barometric_relative"), std::string::npos);
  ASSERT_EQ(log.images.size(), 4u);
  ASSERT_EQ(log.ins.size(), 8u);
  ASSERT_EQ(log.altimeter.size(), 4u);
  ASSERT_EQ(log.truth.size(), 4u);
  const double times[] = {0.25, 2.5, 4.25, 6.25};
  for (int i = 0; i < 4; ++i) {
    const image_t& img = log.images[static_cast<size_t>(i)];
    const int64_t t = 1714557600000000 + std::llround(times[i] * 1e6);
    EXPECT_EQ(img.utime, t);
    EXPECT_EQ(img.width, 160);
    EXPECT_EQ(img.height, 120);
    EXPECT_EQ(img.pixel_format, image_t::PIXEL_MONO8);
    EXPECT_EQ(img.time_quality, image_t::TIME_CAMERA_CLOCK);
    EXPECT_EQ(img.size, 160 * 120);
    // INS bracketing the frame with its attitude: gimbal yaw = body yaw (mount [0, 0, 90]),
    // gimbal pitch -90 = level; the last photo's 5 deg tilt is the body's pitch (nose up).
    const ins_t& before = log.ins[2 * static_cast<size_t>(i)];
    const ins_t& after = log.ins[2 * static_cast<size_t>(i) + 1];
    EXPECT_EQ(before.utime, t - 1000);
    EXPECT_EQ(after.utime, t + 1000);
    EXPECT_NEAR(angle_difference(before.yaw, deg_to_rad(yaws[i])), 0.0, 1e-9) << i;
    EXPECT_NEAR(before.roll, 0.0, 1e-9);
    EXPECT_NEAR(before.pitch, i == 3 ? deg_to_rad(5.0) : 0.0, 1e-9) << i;
    EXPECT_DOUBLE_EQ(after.yaw, before.yaw);
    const altimeter_t& a = log.altimeter[static_cast<size_t>(i)];
    EXPECT_EQ(a.utime, t - 1000);
    EXPECT_DOUBLE_EQ(a.range_m, 40.0 + i);
    // world down in the body frame
    const Eigen::Vector3d down = rotation_from_rpy(before.roll, before.pitch, before.yaw).transpose() * Eigen::Vector3d::UnitZ();
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(a.beam_body[k], down[k], 1e-12);
    const ground_truth_t& g = log.truth[static_cast<size_t>(i)];
    EXPECT_EQ(g.utime, t);
    EXPECT_EQ(g.kind, ground_truth_t::KIND_FRAME);
    EXPECT_NEAR(g.position_ned[0], 11.12 * i, 0.05 * i + 1e-6);  // 0.0001 deg of latitude ~ 11.12 m
    EXPECT_NEAR(g.position_ned[1], 0.0, 1e-3);
    EXPECT_NEAR(g.position_ned[2], -1.0 * i, 1e-9);
  }
  // The config replay runs with: the camera and the sparse-stream limits.
  const Config c = Config::load_file(s.yaml_path);
  EXPECT_EQ(c.section("camera").get<int>("width"), 160);
  EXPECT_DOUBLE_EQ(c.section("camera").get<double>("fx"), 150.0);
  EXPECT_DOUBLE_EQ(c.section("camera").get<std::vector<double>>("distortion")[0], -0.1);
  EXPECT_DOUBLE_EQ(c.section("camera").get<std::vector<double>>("mount_rpy_deg")[2], 90.0);
  EXPECT_EQ(c.section("tracker").get<std::string>("mode"), "descriptor");
  EXPECT_GT(c.section("tracker").get<double>("max_gap_s"), 2.25);
  EXPECT_GT(c.section("vo_solver").section("sync").get<double>("max_frame_interval_ms"), 2250.0);
  EXPECT_GT(c.section("yaw_fusion").get<double>("max_delta_interval_s"), 2.25);
  EXPECT_GT(c.section("input_checks").get<double>("max_ahead_s"), 2.25);
  EXPECT_TRUE(c.section("vo_solver").has("variant"));  // the rest of default.yaml is kept
  // A barometric height above take-off: the vertical follows it.
  EXPECT_EQ(c.section("yaw_fusion").get<std::string>("altitude_mode"), "barometric");
  EXPECT_DOUBLE_EQ(c.section("yaw_fusion").get<double>("altimeter_stddev_m"), 0.3);
  EXPECT_DOUBLE_EQ(c.section("yaw_fusion").get<double>("altimeter_gate_sigma"), 3.0);
  EXPECT_EQ(c.section("yaw_fusion").get<int>("altimeter_max_consecutive_rejections"), 1);
}

// senseFly: roll right wing down +, pitch nose up +, heading clockwise from north (README evidence).
// The attitude accuracy figures a config holds (attitude_accuracy.h: where the import writes them).
struct WrittenAttitudeAccuracy {
  double roll_pitch_deg, vo_yaw_deg, tilt_prior_deg, ins_yaw_deg, max_ins_yaw_deg;
};
WrittenAttitudeAccuracy written_attitude_accuracy(const std::string& yaml_path) {
  const Config config = Config::load_file(yaml_path);
  const Config uncertainty = config.section("vo_solver").section("uncertainty");
  const Config yaw_fusion = config.section("yaw_fusion");
  return {uncertainty.get<double>("roll_pitch_stddev_deg"), uncertainty.get<double>("yaw_stddev_deg"),
          config.section("vo_solver").section("feature_depth").get<double>("ins_tilt_sigma_deg"),
          yaw_fusion.get<double>("ins_yaw_stddev_deg"), yaw_fusion.get<double>("max_ins_yaw_stddev_deg")};
}

TEST(PhotoImport, SenseflyAttitudeAndInterval) {
  TempDir dir("import_sensefly");
  std::filesystem::create_directories(dir.file("photos"));
  for (int i = 0; i < 3; ++i) {
    PhotoTags t;
    t.dji = false;
    t.time = "";  // no EXIF time: --interval gives it
    t.subsec = "";
    t.roll = 10.0 * i;
    t.pitch = -3.0;
    t.yaw = 200.0;
    t.lat = 41.0 + 0.0002 * i;
    write_photo(dir.file("photos/IMG_" + std::to_string(i) + ".jpg"), t);
  }
  ImportOptions o = photo_options(dir);
  o.focal_px = 250.0;
  std::string e = import_error(o);
  EXPECT_NE(e.find("IMG_0.jpg: no time"), std::string::npos) << e;
  o.interval_s = 5.0;
  const ImportSummary s = run_import(o);
  EXPECT_EQ(s.frames_written, 3);
  EXPECT_EQ(s.attitude_source, "sensefly");
  EXPECT_DOUBLE_EQ(s.median_interval_s, 5.0);
  EXPECT_EQ(s.camera.source, "--focal-px");
  EXPECT_DOUBLE_EQ(s.mount_rpy_deg[2], kSenseflyMount[2]);
  const LogContents log = read_log(s.log_path);
  ASSERT_EQ(log.ins.size(), 6u);
  for (int i = 0; i < 3; ++i) {
    const ins_t& m = log.ins[2 * static_cast<size_t>(i)];
    EXPECT_NEAR(m.roll, deg_to_rad(kSenseflyRollSign * 10.0 * i), 1e-9);
    EXPECT_NEAR(m.pitch, deg_to_rad(kSenseflyPitchSign * -3.0), 1e-9);
    EXPECT_NEAR(angle_difference(m.yaw, deg_to_rad(200.0)), 0.0, 1e-9);
    EXPECT_EQ(log.images[static_cast<size_t>(i)].utime - log.images[0].utime, 5000000LL * i);
  }
  // The autopilot's angles are not an INS: the config says how well they are known.
  const WrittenAttitudeAccuracy written = written_attitude_accuracy(s.yaml_path);
  EXPECT_DOUBLE_EQ(written.roll_pitch_deg, 4.0);
  EXPECT_DOUBLE_EQ(written.vo_yaw_deg, 3.0);
  EXPECT_DOUBLE_EQ(written.tilt_prior_deg, 4.0);
  EXPECT_DOUBLE_EQ(written.ins_yaw_deg, 3.0);
  EXPECT_DOUBLE_EQ(s.attitude_accuracy.roll_pitch_stddev_deg, 4.0);
  EXPECT_NE(summary_text(s).find("attitude accuracy: roll/pitch 4.00 deg, heading 3.00 deg"), std::string::npos)
      << summary_text(s);
  EXPECT_NE(summary_json(s).find("\"attitude_accuracy\":{\"roll_pitch_stddev_deg\":4"), std::string::npos)
      << summary_json(s);

  // The user's figures replace the source's; the tilt prior stops at its range's 5 deg, and
  // yaw fusion's limit on a usable INS heading moves up to the heading's sigma.
  o.attitude_stddev_deg = 8.0;
  o.heading_stddev_deg = 12.0;
  const ImportSummary given = run_import(o);
  const WrittenAttitudeAccuracy given_written = written_attitude_accuracy(given.yaml_path);
  EXPECT_DOUBLE_EQ(given_written.roll_pitch_deg, 8.0);
  EXPECT_DOUBLE_EQ(given_written.tilt_prior_deg, 5.0);
  EXPECT_DOUBLE_EQ(given_written.ins_yaw_deg, 12.0);
  EXPECT_DOUBLE_EQ(given_written.max_ins_yaw_deg, 12.0);
  EXPECT_NE(given.attitude_accuracy.basis.find("as given"), std::string::npos);

  o.attitude_stddev_deg = kMaxAttitudeStddevDeg + 1.0;
  EXPECT_THROW(
      {
        try {
          run_import(o);
        } catch (const std::invalid_argument& e) {
          EXPECT_NE(std::string(e.what()).find("--attitude-stddev-deg must be in (0, 30]"), std::string::npos)
              << e.what();
          throw;
        }
      },
      std::invalid_argument);
  o.attitude_stddev_deg = 0.0;
  o.heading_stddev_deg = -1.0;
  EXPECT_THROW(run_import(o), std::invalid_argument);
}

TEST(AttitudeAccuracy, EverySourceHasFiguresAndAnUnknownOneIsNamed) {
  for (const std::string source : {"sensefly", "dji_gimbal", "dji_flight", "srt_gimbal", "srt_flight"}) {
    const AttitudeAccuracy a = attitude_accuracy_of_source(source);
    EXPECT_FALSE(a.from_base_config) << source;
    EXPECT_GT(a.roll_pitch_stddev_deg, 0.0) << source;
    EXPECT_GT(a.heading_stddev_deg, 0.0) << source;
    EXPECT_FALSE(a.basis.empty()) << source;
  }
  // A gimbal holds the camera level better than the body's own angles say it is.
  EXPECT_LT(attitude_accuracy_of_source("dji_gimbal").roll_pitch_stddev_deg,
            attitude_accuracy_of_source("dji_flight").roll_pitch_stddev_deg);
  EXPECT_TRUE(attitude_accuracy_of_source("csv_body").from_base_config);
  try {
    attitude_accuracy_of_source("gps");
    ADD_FAILURE() << "no throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'gps'"), std::string::npos) << e.what();
  }
}

TEST(PhotoImport, BadPhotosNamedOrSkipped) {
  TempDir dir("import_bad");
  std::filesystem::create_directories(dir.file("photos"));
  PhotoTags good;
  write_photo(dir.file("photos/a.jpg"), good);
  PhotoTags no_attitude = good;
  no_attitude.attitude = false;
  no_attitude.time = "2024:05:01 10:00:05";
  write_photo(dir.file("photos/b.jpg"), no_attitude);
  PhotoTags earlier = good;
  earlier.time = "2024:05:01 09:59:59";
  write_photo(dir.file("photos/c.jpg"), earlier);
  PhotoTags bigger = good;
  bigger.time = "2024:05:01 10:00:10";
  write_photo(dir.file("photos/d.jpg"), bigger, 400, 300);
  {
    std::ofstream junk(dir.file("photos/e.jpg"));
    junk << "not a jpeg";
  }
  PhotoTags last = good;
  last.time = "2024:05:01 10:00:20";
  write_photo(dir.file("photos/f.jpg"), last);
  write_camera(dir.file("cam.yaml"), 320, 240, 300.0);
  ImportOptions o = photo_options(dir);
  o.camera_file = dir.file("cam.yaml");
  // each failure in turn, naming its file
  std::string e = import_error(o);
  EXPECT_NE(e.find("b.jpg: no attitude"), std::string::npos) << e;
  std::filesystem::remove(dir.file("photos/b.jpg"));
  e = import_error(o);
  EXPECT_NE(e.find("c.jpg: time"), std::string::npos) << e;
  EXPECT_NE(e.find("is not after the previous frame"), std::string::npos) << e;
  write_photo(dir.file("photos/b.jpg"), no_attitude);
  o.skip_bad = true;
  const ImportSummary s = run_import(o);
  EXPECT_EQ(s.frames_written, 2);  // a and f
  ASSERT_EQ(s.skipped.size(), 4u);
  std::map<std::string, std::string> why;
  for (const SkippedInput& k : s.skipped) why[std::filesystem::path(k.where).filename().string()] = k.reason;
  EXPECT_NE(why["b.jpg"].find("no attitude"), std::string::npos);
  EXPECT_NE(why["c.jpg"].find("not after"), std::string::npos);
  EXPECT_NE(why["d.jpg"].find("photo is 400x300 but"), std::string::npos) << why["d.jpg"];
  EXPECT_NE(why["d.jpg"].find("the flight's are 320x240 (4 of the 5 photos, the first "), std::string::npos)
      << why["d.jpg"];
  EXPECT_NE(why["d.jpg"].find("a.jpg): one image size per import"), std::string::npos) << why["d.jpg"];
  EXPECT_NE(why["e.jpg"].find("cannot read metadata"), std::string::npos) << why["e.jpg"];
  const LogContents log = read_log(s.log_path);
  EXPECT_EQ(log.images.size(), 2u);
  EXPECT_NE(log.config.at(0).yaml.find("skipped: 4"), std::string::npos);
  // without --skip-bad the size mismatch alone fails too
  o.skip_bad = false;
  for (const char* f : {"b.jpg", "c.jpg", "e.jpg"}) std::filesystem::remove(dir.file(std::string("photos/") + f));
  e = import_error(o);
  EXPECT_NE(e.find("d.jpg: photo is 400x300"), std::string::npos) << e;
}

// A malformed XMP value is an error naming file and key; EXIF 35 mm focal length gives a camera with a warning.
TEST(PhotoImport, MalformedXmpAndExifCamera) {
  TempDir dir("import_xmp");
  std::filesystem::create_directories(dir.file("photos"));
  PhotoTags t;
  write_photo(dir.file("photos/p0.jpg"), t, 360, 240);
  t.time = "2024:05:01 10:00:05";
  write_photo(dir.file("photos/p1.jpg"), t, 360, 240);
  {
    auto image = Exiv2::ImageFactory::open(dir.file("photos/p0.jpg"));
    image->readMetadata();
    image->exifData()["Exif.Photo.FocalLengthIn35mmFilm"] = uint16_t{24};
    image->writeMetadata();
    image = Exiv2::ImageFactory::open(dir.file("photos/p1.jpg"));
    image->readMetadata();
    image->xmpData()["Xmp.drone-dji.GimbalYawDegree"] = "north";
    image->writeMetadata();
  }
  ImportOptions o = photo_options(dir);
  const std::string e = import_error(o);
  EXPECT_NE(e.find("p1.jpg: Xmp.drone-dji.GimbalYawDegree is not a number: 'north'"), std::string::npos) << e;
  o.skip_bad = true;
  const ImportSummary s = run_import(o);
  EXPECT_EQ(s.frames_written, 1);
  EXPECT_EQ(s.camera.source, "EXIF FocalLengthIn35mmFilm");
  EXPECT_NEAR(s.camera.fx, 24.0 / std::hypot(36.0, 24.0) * std::hypot(360.0, 240.0), 1e-9);  // = 240 px
  EXPECT_NEAR(s.camera.fx, 240.0, 1e-9);
  ASSERT_EQ(s.warnings.size(), 1u);
  EXPECT_NE(s.warnings[0].find("35 mm equivalent"), std::string::npos);
}

// 12 MP photos (a DJI Phantom 3's 4000x3000) come at the working resolution
// (docs/own-flight.md, "The working resolution"): shrunk by the smallest whole
// factor that brings the long side to at most 1000 px (1/4 -> 1000x750), the
// intrinsics scaled exactly with the images. --scale overrides it (1: full
// size), and a calibration at the working size is taken as it is.
TEST(PhotoImport, TwelveMegapixelPhotosAtTheWorkingResolution) {
  TempDir dir("import_12mp");
  std::filesystem::create_directories(dir.file("photos"));
  for (int i = 0; i < 2; ++i) {
    cv::Mat photo;  // smooth content: a JPEG of 12 MP of noise is ~20 MB
    cv::resize(texture(400, 300, i + 1), photo, cv::Size(4000, 3000), 0, 0, cv::INTER_LINEAR);
    const std::string path = dir.file("photos/DJI_000" + std::to_string(i) + ".JPG");
    ASSERT_TRUE(cv::imwrite(path, photo));
    PhotoTags t;
    t.time = "2024:05:01 10:00:0" + std::to_string(2 * i);
    t.lat = 47.5 + 0.0001 * i;
    tag_photo(path, t);
  }
  const auto write_calibration = [&](const std::string& name, int w, int h, double fx, double fy, double cx, double cy) {
    cv::FileStorage fs(dir.file(name), cv::FileStorage::WRITE);
    fs << "image_width" << w << "image_height" << h;
    fs << "camera_matrix" << cv::Mat(cv::Matx33d(fx, 0, cx, 0, fy, cy, 0, 0, 1));
    fs << "distortion_coefficients" << cv::Mat(cv::Matx<double, 1, 5>(-0.1, 0.01, 0.001, 0, 0));
  };
  // The files' calibration, principal point off centre.
  write_calibration("full.yaml", 4000, 3000, 2311.0, 2309.0, 2010.5, 1490.5);
  ImportOptions o = photo_options(dir);
  o.camera_file = dir.file("full.yaml");
  const ImportSummary s = run_import(o);  // no --scale
  EXPECT_DOUBLE_EQ(s.resolution.scale, 0.25);
  EXPECT_EQ(s.camera.width, 1000);
  EXPECT_EQ(s.camera.height, 750);
  EXPECT_DOUBLE_EQ(s.camera.fx, 577.75);
  EXPECT_DOUBLE_EQ(s.camera.fy, 577.25);
  EXPECT_DOUBLE_EQ(s.camera.cx, 502.25);  // pixel centres kept: (2010.5 + 0.5) / 4 - 0.5
  EXPECT_DOUBLE_EQ(s.camera.cy, 372.25);
  EXPECT_DOUBLE_EQ(s.camera.distortion[2], 0.001);  // normalized coordinates: unchanged
  EXPECT_NE(summary_text(s).find("working resolution 1000x750 (scale 1/4: long side 4000 px over 1000 px)"),
            std::string::npos)
      << summary_text(s);
  EXPECT_NE(summary_json(s).find("\"scale_rule\":\"1/4: long side 4000 px over 1000 px\""), std::string::npos)
      << summary_json(s);
  const LogContents log = read_log(s.log_path);
  ASSERT_EQ(log.images.size(), 2u);
  for (const image_t& img : log.images) {
    EXPECT_EQ(img.width, 1000);
    EXPECT_EQ(img.height, 750);
    EXPECT_EQ(img.size, 1000 * 750);
  }
  ASSERT_EQ(log.config.size(), 1u);
  EXPECT_NE(log.config[0].yaml.find("scale: 0.25"), std::string::npos) << log.config[0].yaml;
  const Config c = Config::load_file(s.yaml_path);
  EXPECT_EQ(c.section("camera").get<int>("width"), 1000);
  EXPECT_DOUBLE_EQ(c.section("camera").get<double>("fx"), 577.75);

  // --scale overrides the rule; 1 is full size.
  o.scale = 1.0;
  ImportSummary full = run_import(o);
  EXPECT_EQ(full.camera.width, 4000);
  EXPECT_EQ(full.camera.height, 3000);
  EXPECT_DOUBLE_EQ(full.camera.fx, 2311.0);
  EXPECT_DOUBLE_EQ(full.camera.cx, 2010.5);
  EXPECT_EQ(read_log(full.log_path).images.at(0).width, 4000);
  EXPECT_NE(summary_text(full).find("working resolution 4000x3000 (scale 1: --scale)"), std::string::npos)
      << summary_text(full);
  o.scale = 0.5;
  full = run_import(o);
  EXPECT_EQ(full.camera.width, 2000);
  EXPECT_EQ(full.camera.height, 1500);
  EXPECT_DOUBLE_EQ(full.camera.fx, 1155.5);

  // A calibration at the working size is used as it is; one at neither size is an error naming the file.
  write_calibration("working.yaml", 1000, 750, 577.75, 577.25, 502.25, 372.25);
  o.scale = 0.0;
  o.camera_file = dir.file("working.yaml");
  const ImportSummary w = run_import(o);
  EXPECT_EQ(w.camera.width, 1000);
  EXPECT_DOUBLE_EQ(w.camera.fx, 577.75);
  EXPECT_DOUBLE_EQ(w.camera.cx, 502.25);
  write_calibration("other.yaml", 2000, 1500, 1155.5, 1155.5, 999.5, 749.5);
  o.camera_file = dir.file("other.yaml");
  const std::string error = import_error(o);
  EXPECT_NE(error.find("DJI_0000.JPG: frame is 4000x3000 but the camera"), std::string::npos) << error;
  EXPECT_NE(error.find("neither the files' size nor the working size); give --scale 0.5 for a calibration at that size"),
            std::string::npos)
      << error;

  // --scale is checked at the start.
  o.scale = 1.5;
  EXPECT_THROW(o.Check(), std::invalid_argument);
  o.scale = -0.5;
  EXPECT_THROW(o.Check(), std::invalid_argument);
}

// The binary: exit 2 with the file named on a bad photo.
TEST(PhotoImport, ToolExitsTwoOnBadInput) {
  TempDir dir("import_tool");
  std::filesystem::create_directories(dir.file("photos"));
  PhotoTags t;
  t.attitude = false;
  write_photo(dir.file("photos/x.jpg"), t);
  const char* bin = std::getenv("NADIR_BIN_DIR");
  ASSERT_NE(bin, nullptr);
  const std::string cmd = std::string(bin) + "/nadir_import --photos " + dir.file("photos") + " --focal-px 300 --out " +
                          dir.file("o") + " 2> " + dir.file("err.txt");
  const int rc = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(rc));
  EXPECT_EQ(WEXITSTATUS(rc), 2);
  std::ifstream in(dir.file("err.txt"));
  const std::string err((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(err.find("x.jpg: no attitude"), std::string::npos) << err;
  EXPECT_FALSE(std::filesystem::exists(dir.file("o.lcmlog")));
}

// The binary: an attitude figure out of (0, 30] is refused before anything is read, naming the option.
TEST(PhotoImport, ToolRefusesAttitudeFiguresOutOfRange) {
  TempDir dir("import_attitude_figures");
  const char* bin = std::getenv("NADIR_BIN_DIR");
  ASSERT_NE(bin, nullptr);
  for (const std::string option : {"--attitude-stddev-deg", "--heading-stddev-deg"}) {
    for (const std::string value : {"0", "-1", "31", "many"}) {
      const std::string cmd = std::string(bin) + "/nadir_import --photos " + dir.file("none") + " " + option + " " +
                              value + " --out " + dir.file("o") + " 2> " + dir.file("err.txt");
      const int rc = std::system(cmd.c_str());
      ASSERT_TRUE(WIFEXITED(rc));
      EXPECT_NE(WEXITSTATUS(rc), 0) << option << " " << value;
      std::ifstream in(dir.file("err.txt"));
      const std::string err((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
      EXPECT_NE(err.find(option + ": must be in (0, 30] (leave it out for the attitude source's), not " + value),
                std::string::npos)
          << err;
    }
  }
  EXPECT_FALSE(std::filesystem::exists(dir.file("o.lcmlog")));
}

// The binary: --scale out of (0, 1] is refused before anything is read (0 is not "automatic": leave it out).
TEST(PhotoImport, ToolRefusesScaleOutOfRange) {
  TempDir dir("import_scale");
  const char* bin = std::getenv("NADIR_BIN_DIR");
  ASSERT_NE(bin, nullptr);
  for (const std::string value : {"0", "-0.5", "1.5", "half"}) {
    const std::string cmd = std::string(bin) + "/nadir_import --photos " + dir.file("none") + " --scale " + value +
                            " --out " + dir.file("o") + " 2> " + dir.file("err.txt");
    const int rc = std::system(cmd.c_str());
    ASSERT_TRUE(WIFEXITED(rc));
    EXPECT_NE(WEXITSTATUS(rc), 0) << value;
    std::ifstream in(dir.file("err.txt"));
    const std::string err((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_NE(err.find("--scale: must be in (0, 1] (1: full size; leave it out for the working resolution), not " + value),
              std::string::npos)
        << err;
  }
  EXPECT_FALSE(std::filesystem::exists(dir.file("o.lcmlog")));
}

// What a camera writes about itself: EXIF Model, 35 mm equivalent, the size
// it wrote, DJI's XMP calibration (each only when given).
struct CameraTags {
  std::string model;
  int focal_35mm = 0;
  int written_width = 0, written_height = 0;  // Exif.Photo.PixelX/YDimension
  double calibrated_focal = 0, center_x = -1, center_y = -1;
};

void tag_camera(const std::string& path, const CameraTags& c) {
  auto image = Exiv2::ImageFactory::open(path);
  image->readMetadata();
  Exiv2::ExifData& exif = image->exifData();
  if (!c.model.empty()) {
    exif["Exif.Image.Make"] = "DJI";
    exif["Exif.Image.Model"] = c.model;
  }
  if (c.focal_35mm > 0) exif["Exif.Photo.FocalLengthIn35mmFilm"] = static_cast<uint16_t>(c.focal_35mm);
  if (c.written_width > 0) {
    exif["Exif.Photo.PixelXDimension"] = static_cast<uint32_t>(c.written_width);
    exif["Exif.Photo.PixelYDimension"] = static_cast<uint32_t>(c.written_height);
  }
  Exiv2::XmpData& xmp = image->xmpData();
  char text[32];
  if (c.calibrated_focal > 0) {
    std::snprintf(text, sizeof(text), "%.4f", c.calibrated_focal);
    xmp["Xmp.drone-dji.CalibratedFocalLength"] = std::string(text);
  }
  if (c.center_x >= 0) {
    std::snprintf(text, sizeof(text), "%.4f", c.center_x);
    xmp["Xmp.drone-dji.CalibratedOpticalCenterX"] = std::string(text);
    std::snprintf(text, sizeof(text), "%.4f", c.center_y);
    xmp["Xmp.drone-dji.CalibratedOpticalCenterY"] = std::string(text);
  }
  image->writeMetadata();
}

// Two photos 5 s apart of one camera, `w` x `h`, in DIR/photos.
void write_camera_photos(const TempDir& dir, const CameraTags& c, int w, int h) {
  std::filesystem::create_directories(dir.file("photos"));
  PhotoTags t;
  for (int i = 0; i < 2; ++i) {
    const std::string path = dir.file("photos/p" + std::to_string(i) + ".jpg");
    t.time = "2024:05:01 10:00:0" + std::to_string(5 * i);
    write_photo(path, t, w, h, i + 1);
    tag_camera(path, c);
  }
}

// The 35 mm equivalent is on the diagonal of the sensor's full frame: a 16:9
// photo from a 4:3 sensor (DJI FC300X) takes the 4:3 frame's diagonal at the
// photo's width, not its own (8.2 % shorter).
TEST(PhotoCamera, SixteenByNineCropOfAFourByThreeSensor) {
  // The worked example of docs/own-flight.md: FC300X, 20 mm equivalent, 4000x2250.
  EXPECT_NEAR(native_frame_diagonal_px(4000, 2250, 4000, 3000), 5000.0, 1e-9);
  EXPECT_NEAR(20.0 / kFullFrameDiagonalMm * 5000.0, 2311.25, 0.01);
  EXPECT_NEAR(20.0 / kFullFrameDiagonalMm * std::hypot(4000.0, 2250.0), 2121.45, 0.01);
  // Portrait photos and squarer crops keep the side the sensor keeps.
  EXPECT_NEAR(native_frame_diagonal_px(2250, 4000, 4000, 3000), 5000.0, 1e-9);
  EXPECT_NEAR(native_frame_diagonal_px(3000, 3000, 4000, 3000), 5000.0, 1e-9);
  EXPECT_NEAR(native_frame_diagonal_px(4000, 3000, 4000, 3000), 5000.0, 1e-9);

  TempDir dir("import_crop");
  CameraTags c;
  c.model = "FC300X";
  c.focal_35mm = 20;
  write_camera_photos(dir, c, 400, 225);  // a 16:9 photo, resized
  const ImportSummary s = run_import(photo_options(dir));
  const double native = 20.0 / kFullFrameDiagonalMm * 500.0;                       // 231.1 px
  const double own_diagonal = 20.0 / kFullFrameDiagonalMm * std::hypot(400.0, 225.0);  // 212.1 px
  EXPECT_NEAR(s.camera.fx, native, 1e-9);
  EXPECT_NEAR(s.camera.fy, native, 1e-9);
  EXPECT_NEAR(s.camera.fx / own_diagonal - 1.0, 0.0897, 0.001);  // the 16:9 diagonal's answer is 8.2 % short
  EXPECT_EQ(s.camera.source, "EXIF FocalLengthIn35mmFilm");
  EXPECT_EQ(s.camera_model, "FC300X");
  EXPECT_NE(s.focal_rule.find("native 4000x3000 frame"), std::string::npos) << s.focal_rule;
  ASSERT_EQ(s.warnings.size(), 1u);
  EXPECT_NE(s.warnings[0].find("camera 'FC300X' (DJI): focal 231.1 px"), std::string::npos) << s.warnings[0];
  EXPECT_NE(s.warnings[0].find("the 400x225 photo is a crop"), std::string::npos) << s.warnings[0];
  const LogContents log = read_log(s.log_path);
  EXPECT_NE(log.config.at(0).yaml.find("camera_model: FC300X"), std::string::npos) << log.config.at(0).yaml;
  // A model the table does not know: the photo is taken as the full frame, and the warning says so.
  TempDir other("import_unknown_model");
  c.model = "XYZ-1";
  write_camera_photos(other, c, 400, 225);
  const ImportSummary u = run_import(photo_options(other));
  EXPECT_NEAR(u.camera.fx, own_diagonal, 1e-9);
  ASSERT_EQ(u.warnings.size(), 1u);
  EXPECT_NE(u.warnings[0].find("camera 'XYZ-1' (DJI)"), std::string::npos) << u.warnings[0];
  EXPECT_NE(u.warnings[0].find("model not in the camera table: the 400x225 photo taken as the sensor's full frame"),
            std::string::npos)
      << u.warnings[0];
}

// DJI's XMP calibration comes first and is used as written; a resized file scales it.
TEST(PhotoCamera, DjiXmpCalibrationUsedAsWritten) {
  TempDir dir("import_xmp_calibration");
  CameraTags c;
  c.model = "FC6360";
  c.focal_35mm = 20;  // ignored: the calibration comes first
  c.written_width = 320, c.written_height = 240;
  c.calibrated_focal = 287.3125, c.center_x = 161.25, c.center_y = 117.5;
  write_camera_photos(dir, c, 320, 240);
  const ImportSummary s = run_import(photo_options(dir));
  EXPECT_EQ(s.camera.source, "XMP drone-dji:CalibratedFocalLength");
  EXPECT_DOUBLE_EQ(s.camera.fx, 287.3125);
  EXPECT_DOUBLE_EQ(s.camera.fy, 287.3125);
  EXPECT_DOUBLE_EQ(s.camera.cx, 161.25);
  EXPECT_DOUBLE_EQ(s.camera.cy, 117.5);
  ASSERT_EQ(s.warnings.size(), 1u);
  EXPECT_NE(s.warnings[0].find("camera 'FC6360' (DJI): focal 287.31 px from the calibrated focal"), std::string::npos)
      << s.warnings[0];
  // The camera wrote 640x480; the file was halved since.
  TempDir half("import_xmp_resized");
  c.written_width = 640, c.written_height = 480;
  c.calibrated_focal = 574.625, c.center_x = 322.75, c.center_y = 235.5;
  write_camera_photos(half, c, 320, 240);
  const ImportSummary h = run_import(photo_options(half));
  EXPECT_DOUBLE_EQ(h.camera.fx, 287.3125);
  EXPECT_DOUBLE_EQ(h.camera.cx, 161.125);  // pixel centres kept: (322.75 + 0.5) / 2 - 0.5
  EXPECT_DOUBLE_EQ(h.camera.cy, 117.5);
  EXPECT_NE(h.focal_rule.find("scaled by 0.5"), std::string::npos) << h.focal_rule;
}

// DJI's DewarpData as its manuals give it (a Phantom 4 RTK's, spaces and all), and text that is not it.
TEST(PhotoCamera, DewarpDataParsedOrRefused) {
  std::array<double, 9> d{};
  ASSERT_TRUE(parse_dewarp_data(" 2018-03-13;3659.780000000000,3653.170000000000,-7.710000000000,45.900000000000,"
                                "-0.269478000000,0.115681000000,-0.000087561900,-0.000306177000,-0.035762800000",
                                &d));
  const std::array<double, 9> expected{3659.78, 3653.17, -7.71, 45.9, -0.269478, 0.115681, -0.0000875619,
                                       -0.000306177, -0.0357628};
  for (size_t k = 0; k < 9; ++k) EXPECT_DOUBLE_EQ(d[k], expected[k]) << k;
  EXPECT_TRUE(parse_dewarp_data("100,100,0,0,0,0,0,0,0", &d));  // no date
  EXPECT_FALSE(parse_dewarp_data("2018-03-13;3659.78,3653.17,-7.71,45.9,-0.27,0.11,0,0", &d));      // 8 numbers
  EXPECT_FALSE(parse_dewarp_data("2018-03-13;3659.78,3653.17,-7.71,45.9,-0.27,0.11,0,0,0,1", &d));  // 10
  EXPECT_FALSE(parse_dewarp_data("2018-03-13;0,3653.17,-7.71,45.9,-0.27,0.11,0,0,0", &d));          // fx 0
  EXPECT_FALSE(parse_dewarp_data("2018-03-13;3659.78,x,-7.71,45.9,-0.27,0.11,0,0,0", &d));
  EXPECT_FALSE(parse_dewarp_data("2018-03-13;3659.78,nan,-7.71,45.9,-0.27,0.11,0,0,0", &d));
}

// No focal length in the file: the error names the file and the model, says how to give one, and
// what the camera table knows of the model.
TEST(PhotoCamera, NoFocalLengthNamesFileModelAndTheWayOut) {
  TempDir dir("import_no_focal");
  CameraTags c;
  c.model = "XYZ-1";
  write_camera_photos(dir, c, 320, 256);
  std::string e = import_error(photo_options(dir));
  EXPECT_NE(e.find("p0.jpg: no focal length in the file"), std::string::npos) << e;
  EXPECT_NE(e.find("camera 'XYZ-1' (DJI)"), std::string::npos) << e;
  EXPECT_NE(e.find("give --camera FILE (an OpenCV calibration) or --focal-px F"), std::string::npos) << e;
  EXPECT_EQ(e.find("camera table"), std::string::npos) << e;
  // A thermal camera the table knows (640x512, 12 um, 9 mm): nominally 750 px, 375 at half size.
  TempDir thermal("import_no_focal_thermal");
  c.model = "MAVIC2-ENTERPRISE-ADVANCED";
  write_camera_photos(thermal, c, 320, 256);
  e = import_error(photo_options(thermal));
  EXPECT_NE(e.find("p0.jpg: no focal length in the file"), std::string::npos) << e;
  EXPECT_NE(e.find("the camera table's DJI Mavic 2 Enterprise Advanced, thermal camera has a 9 mm lens"),
            std::string::npos)
      << e;
  EXPECT_NE(e.find("nominally --focal-px 375 for this 320x256 photo"), std::string::npos) << e;
  // The binary: exit 2, the message on stderr.
  const char* bin = std::getenv("NADIR_BIN_DIR");
  ASSERT_NE(bin, nullptr);
  const std::string cmd = std::string(bin) + "/nadir_import --photos " + thermal.file("photos") + " --out " +
                          thermal.file("o") + " 2> " + thermal.file("err.txt");
  const int rc = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(rc));
  EXPECT_EQ(WEXITSTATUS(rc), 2);
  std::ifstream in(thermal.file("err.txt"));
  const std::string err((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(err.find("p0.jpg: no focal length in the file"), std::string::npos) << err;
  // ... and the focal length given on the command line imports.
  ImportOptions o = photo_options(thermal);
  o.focal_px = 375.0;
  EXPECT_EQ(run_import(o).frames_written, 2);
}

// A folder of two cameras: the first photo of the other camera is named with both models; --skip-bad
// skips and counts them.
TEST(PhotoCamera, MixedCamerasNamedOrSkipped) {
  TempDir dir("import_mixed");
  CameraTags c;
  c.model = "FC6310";
  c.focal_35mm = 24;
  write_camera_photos(dir, c, 360, 240);
  PhotoTags t;
  t.time = "2024:05:01 10:00:10";
  write_photo(dir.file("photos/p2.jpg"), t, 360, 240, 3);
  c.model = "FC330";
  tag_camera(dir.file("photos/p2.jpg"), c);
  ImportOptions o = photo_options(dir);
  const std::string e = import_error(o);
  EXPECT_NE(e.find("p2.jpg: camera model 'FC330' differs from the flight's 'FC6310'"), std::string::npos) << e;
  EXPECT_NE(e.find("(2 of the 3 photos, the first "), std::string::npos) << e;
  EXPECT_NE(e.find("p0.jpg): one camera per import"), std::string::npos) << e;
  o.skip_bad = true;
  const ImportSummary s = run_import(o);
  EXPECT_EQ(s.frames_written, 2);
  ASSERT_EQ(s.skipped.size(), 1u);
  EXPECT_NE(s.skipped[0].where.find("p2.jpg"), std::string::npos);
  EXPECT_NE(s.skipped[0].reason.find("mixed cameras"), std::string::npos) << s.skipped[0].reason;
  // The odd photo first (a.jpg sorts first): the camera most photos have is still the flight's.
  std::filesystem::rename(dir.file("photos/p2.jpg"), dir.file("photos/a.jpg"));
  PhotoTags t0;
  t0.time = "2024:05:01 09:59:55";
  write_photo(dir.file("photos/a.jpg"), t0, 360, 240, 3);
  tag_camera(dir.file("photos/a.jpg"), c);
  o.skip_bad = false;
  const std::string first = import_error(o);
  EXPECT_NE(first.find("a.jpg: camera model 'FC330' differs from the flight's 'FC6310'"), std::string::npos) << first;
  o.skip_bad = true;
  const ImportSummary k = run_import(o);
  EXPECT_EQ(k.frames_written, 2);
  ASSERT_EQ(k.skipped.size(), 1u);
  EXPECT_NE(k.skipped[0].where.find("a.jpg"), std::string::npos);
}

// Every row of the camera table has a model, a geometry and a source; lookups ignore case and pick
// the camera of the photo's size when one Model names two.
TEST(CameraTable, RowsAndLookup) {
  for (const KnownCamera& k : known_cameras()) {
    SCOPED_TRACE(k.name);
    EXPECT_FALSE(k.models.empty());
    EXPECT_GT(k.sensor_width_mm, k.sensor_height_mm * 0.99);
    EXPECT_GT(k.native_width, 0);
    EXPECT_GT(k.native_height, 0);
    EXPECT_GT(k.focal_mm, 0);
    EXPECT_FALSE(k.source.empty());
    // the sensor's millimetres and its pixels have one aspect (within the rounding of nominal sizes)
    EXPECT_NEAR(k.sensor_width_mm / k.sensor_height_mm, static_cast<double>(k.native_width) / k.native_height, 0.1);
  }
  ASSERT_NE(find_known_camera(" fc300x ", 4000, 2250), nullptr);
  EXPECT_EQ(find_known_camera("FC300X", 4000, 2250)->native_height, 3000);
  EXPECT_EQ(find_known_camera("M3T", 640, 512)->native_width, 640);
  EXPECT_EQ(find_known_camera("M3T", 8000, 6000)->native_width, 8000);
  EXPECT_EQ(find_known_camera("M3T", 4000, 3000)->native_width, 8000);
  EXPECT_EQ(find_known_camera("nadir_sim downward camera", 512, 612), nullptr);
  EXPECT_EQ(find_known_camera("", 512, 612), nullptr);
}

// Video + SRT and video + CSV: one frame per telemetry record.
TEST(VideoImport, SrtAndCsv) {
  TempDir dir("import_video");
  const std::string video = dir.file("v.avi");
  {
    cv::VideoWriter w(video, cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), 10.0, cv::Size(160, 120));
    ASSERT_TRUE(w.isOpened());
    for (int i = 0; i < 5; ++i) w.write(texture(160, 120, i));
  }
  std::ofstream srt(dir.file("v.SRT"));
  for (int i = 0; i < 5; ++i) {
    char times[160];
    std::snprintf(times, sizeof(times), "00:00:00,%03d --> 00:00:00,%03d\nFrameCnt: %d, DiffTime: 100ms\n"
                  "2024-05-01 10:00:00.%03d", 100 * i, 100 * i + 99, i + 1, 100 * i);
    srt << i + 1 << "\n" << times << "\n[latitude: 47.5" << i
        << "] [longitude: 8.25] [rel_alt: 40.0 abs_alt: 500.0] [gb_yaw: " << 45 * i
        << " gb_pitch: -90.0 gb_roll: 0.0]" << (i == 2 ? " [range: 38.5]" : "") << "\n\n";
  }
  srt.close();
  write_camera(dir.file("cam.yaml"), 160, 120, 140.0);
  ImportOptions o;
  o.video = video;
  o.srt = dir.file("v.SRT");
  o.out = dir.file("vid");
  o.camera_file = dir.file("cam.yaml");
  o.config_path = std::string(NADIR_SOURCE_DIR) + "/config/default.yaml";
  // frame 3 has a laser range where the others have barometric height: not one altimeter
  std::string e = import_error(o);
  EXPECT_NE(e.find("v.avi frame 2 (" + o.srt + ":13)"), std::string::npos) << e;
  EXPECT_NE(e.find("altimeter source rangefinder differs"), std::string::npos) << e;
  o.skip_bad = true;
  ImportSummary s = run_import(o);
  EXPECT_EQ(s.frames_written, 4);
  EXPECT_EQ(s.attitude_source, "srt_gimbal");
  EXPECT_NEAR(s.first_time_s, 1714557600.0, 1e-6);
  LogContents log = read_log(s.log_path);
  ASSERT_EQ(log.images.size(), 4u);
  EXPECT_EQ(log.images[2].utime - log.images[0].utime, 300000);
  EXPECT_NEAR(angle_difference(log.ins[4].yaw, deg_to_rad(135.0)), 0.0, 1e-9);

  std::ofstream csv(dir.file("v.csv"));
  csv << "time_s,roll_deg,pitch_deg,yaw_deg,range_m,lat_deg,lon_deg,alt_m\n";
  for (int i = 0; i < 5; ++i) csv << 0.1 * i << ",0,2," << 10 * i << ",39.5,47.5" << i << ",8.25,500\n";
  csv << "0.6,0,0,0,39.5,47.5,8.25,500\n";  // beyond the video's 5 frames
  csv.close();
  o.srt.clear();
  o.csv = dir.file("v.csv");
  o.skip_bad = false;
  e = import_error(o);
  EXPECT_NE(e.find("v.avi frame 6 (" + o.csv + ":7): the video has no such frame"), std::string::npos) << e;
  o.skip_bad = true;
  s = run_import(o);
  EXPECT_EQ(s.frames_written, 5);
  EXPECT_EQ(s.attitude_source, "csv_body");
  EXPECT_EQ(s.altimeter_source, "rangefinder");
  log = read_log(s.log_path);
  EXPECT_NEAR(log.ins[2].pitch, deg_to_rad(2.0), 1e-9);
  EXPECT_NEAR(log.ins[8].yaw, deg_to_rad(40.0), 1e-9);
  EXPECT_DOUBLE_EQ(log.altimeter[4].range_m, 39.5);
  // A rangefinder flight keeps the base config's altitude mode.
  EXPECT_EQ(Config::load_file(s.yaml_path).section("yaw_fusion").get<std::string>("altitude_mode"), "vo_dz");
  // A CSV's attitude is taken to be the base config's INS unless a figure is given; a figure
  // given alone is written alone.
  const WrittenAttitudeAccuracy base = written_attitude_accuracy(o.config_path);
  EXPECT_TRUE(s.attitude_accuracy.from_base_config);
  EXPECT_DOUBLE_EQ(written_attitude_accuracy(s.yaml_path).roll_pitch_deg, base.roll_pitch_deg);
  EXPECT_DOUBLE_EQ(written_attitude_accuracy(s.yaml_path).ins_yaw_deg, base.ins_yaw_deg);
  o.heading_stddev_deg = 2.0;
  s = run_import(o);
  const WrittenAttitudeAccuracy heading_given = written_attitude_accuracy(s.yaml_path);
  EXPECT_DOUBLE_EQ(heading_given.ins_yaw_deg, 2.0);
  EXPECT_DOUBLE_EQ(heading_given.roll_pitch_deg, base.roll_pitch_deg);
  EXPECT_DOUBLE_EQ(heading_given.tilt_prior_deg, base.tilt_prior_deg);
  EXPECT_NE(summary_text(s).find("roll/pitch the base config's, heading 2.00 deg"), std::string::npos)
      << summary_text(s);
}

}  // namespace
}  // namespace nadir::import
