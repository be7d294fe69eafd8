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
#include "tools/import/flight_import.h"

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

void write_photo(const std::string& path, const PhotoTags& t, int w = 320, int h = 240, int seed = 1) {
  ASSERT_TRUE(cv::imwrite(path, texture(w, h, seed)));
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
}

// senseFly: roll right wing down +, pitch nose up +, heading clockwise from north (README evidence).
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
  EXPECT_NE(why["d.jpg"].find("a.jpg is 320x240: one image size per import"), std::string::npos) << why["d.jpg"];
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
}

}  // namespace
}  // namespace nadir::import
