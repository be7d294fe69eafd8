// nadir_export against the simulator's truth: a short flight with a 180 deg
// turn is rendered in-process, exported, and every photo's metadata is read
// back through libexiv2.
#include <gtest/gtest.h>
#include <opencv2/calib3d.hpp>
#include <opencv2/features2d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>

#include <Eigen/Geometry>
#include <cmath>
#include <fstream>
#include <memory>
#include <regex>
#include <sstream>

#include "common/channels.h"
#include "common/config.h"
#include "common/geodetic.h"
#include "common/geometry.h"
#include "common/log_file.h"
#include "common/paths.h"
#include "common/robust_stats.h"
#include "nadir/config_t.hpp"
#include "processes/sim/simulator.h"
#include "tests/common/test_support.h"
#include "tools/export/exporter.h"

namespace nadir::exporter {
namespace {

// 3 s of line, a 180 deg right turn (~10 s at 35 deg bank), then a line: at
// 60 m and 11 m/s as the survey profile, 18 s in all.
constexpr const char* kProfile = R"(
name: export_test
distance_m: 200
speed_mps: 11
altitude_agl_m: 60
initial_heading_deg: 30
pitch_trim_deg: -2.0
oscillation: {roll_deg: 0.8, pitch_deg: 0.6, yaw_deg: 0.4}
reference: {latitude_deg: 40.4406, longitude_deg: -79.9959, height_m: 300.0}
terrain: {relief_scale: 0.2}
legs:
  - {type: straight, distance_m: 33}
  - {type: turn, angle_deg: 180, bank_deg: 35}
  - {type: straight}
)";

double rotation_angle(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  return Eigen::AngleAxisd(a.transpose() * b).angle();
}

class ExportTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new testing::TempDir("export");
    log_path_ = dir_->file("sim.lcmlog");
    Config config = Config::load_file(default_config_path());
    config.apply_override("camera.rate_hz=4.0");  // only the exported frames matter: fewer to render
    const sim::SimCamera camera = sim::SimCamera::from_config(config);
    const sim::SensorOptions sensors =
        sim::SensorOptions::from_config(Config::load_file(checkout_root() + "/config/sim_sensors.yaml"), "standard");
    const sim::FlightProfile profile = sim::FlightProfile::parse(kProfile, "export_test profile");
    sim::SimulatorOptions options;
    options.seed = 3;
    options.camera_yaml = config.section("camera").dump();
    sim::Simulator simulator(profile, camera, sensors, options);
    LogWriter writer(log_path_);
    sim::SimEvent event;
    while (simulator.next(&event)) writer.write(event.utime, event.channel, event.data.data(), event.data.size());
    writer.flush();
    log_ = SimLog::load(log_path_).release();
  }
  static void TearDownTestSuite() {
    delete log_;
    delete dir_;
  }

  static testing::TempDir* dir_;
  static std::string log_path_;
  static SimLog* log_;
};

testing::TempDir* ExportTest::dir_ = nullptr;
std::string ExportTest::log_path_;
SimLog* ExportTest::log_ = nullptr;

TEST_F(ExportTest, PhotoMetadataReadsBackAsTheTruth) {
  PhotoExportOptions options;
  options.interval_s = 1.0;
  const std::string out = dir_->file("photos");
  const PhotoExportResult result = export_photos(*log_, out, options);
  ASSERT_GE(result.photos.size(), 8u);
  const CameraModel turned = turned_camera(log_->camera());
  for (const PhotoRecord& record : result.photos) {
    SCOPED_TRACE(record.file);
    const PhotoMetadata m = read_photo_metadata(out + "/" + record.file);
    // Time: the image's sensor time to the millisecond.
    EXPECT_LE(std::llabs(m.utime - record.utime), 500);
    const ground_truth_t& truth = log_->truth_for_frame(record.utime);
    // GPS: the INS truth position at the exposure (metres on the ground).
    const ins_t& ins = log_->ins()[log_->nearest_ins(truth.utime)];
    const double dt = (truth.utime - ins.utime) * 1e-6;
    const double north_err = (m.latitude_deg - ins.latitude_deg) * 111000.0 - ins.velocity_ned[0] * dt;
    const double east_err =
        (m.longitude_deg - ins.longitude_deg) * 111000.0 * std::cos(deg_to_rad(ins.latitude_deg)) - ins.velocity_ned[1] * dt;
    EXPECT_LT(std::hypot(north_err, east_err), 0.05);
    EXPECT_NEAR(m.relative_altitude_m, -truth.position_ned[2], 1e-3);
    EXPECT_NEAR(m.absolute_altitude_m, 300.0 - truth.position_ned[2], 1e-3);
    EXPECT_NEAR(m.altitude_m, m.absolute_altitude_m, 1e-3);
    // Flight angles: the truth body attitude.
    EXPECT_NEAR(m.flight.roll_deg, rad_to_deg(truth.roll), 1e-5);
    EXPECT_NEAR(m.flight.pitch_deg, rad_to_deg(truth.pitch), 1e-5);
    EXPECT_NEAR(rad_to_deg(angle_difference(deg_to_rad(m.flight.yaw_deg), truth.yaw)), 0.0, 1e-5);
    // Gimbal angles composed as the contract says give the truth camera attitude.
    const Eigen::Matrix3d world_from_body = rotation_from_rpy(truth.roll, truth.pitch, truth.yaw);
    const Eigen::Matrix3d truth_camera = world_from_body * turned.body_from_camera;
    EXPECT_LT(rotation_angle(camera_attitude_from_gimbal(m.gimbal), truth_camera), 1e-4);
    // ... and so does the flight attitude with mount [0, 0, 90] (the importer's mapping).
    const Eigen::Matrix3d mount = rotation_from_rpy(0, 0, deg_to_rad(90.0));
    const Eigen::Matrix3d from_flight =
        rotation_from_rpy(deg_to_rad(m.flight.roll_deg), deg_to_rad(m.flight.pitch_deg), deg_to_rad(m.flight.yaw_deg));
    EXPECT_LT(rotation_angle(from_flight * mount, camera_attitude_from_gimbal(m.gimbal)), 1e-4);
    // Gimbal yaw follows the heading, as on a DJI drone.
    EXPECT_LT(std::fabs(angle_difference(deg_to_rad(m.gimbal.yaw_deg), truth.yaw)), deg_to_rad(45.0));
    EXPECT_EQ(m.width, 512);
    EXPECT_EQ(m.height, 612);
    EXPECT_NEAR(m.focal_length_mm, 398.79 * 5.86e-3, 1e-3);
    EXPECT_NEAR(m.focal_length_35mm, 22.0, 0.5);  // 398.79 px * 43.27 mm / 798 px diagonal
  }
}

TEST_F(ExportTest, InsAttitudeSourceWritesTheMeasuredAttitude) {
  PhotoExportOptions options;
  options.interval_s = 3.0;
  options.attitude = AttitudeSource::kIns;
  const std::string out = dir_->file("photos_ins");
  const PhotoExportResult result = export_photos(*log_, out, options);
  EXPECT_EQ(result.attitude_source, "ins");
  for (const PhotoRecord& record : result.photos) {
    const PhotoMetadata m = read_photo_metadata(out + "/" + record.file);
    const ins_t& ins = log_->ins()[log_->nearest_ins(log_->truth_for_frame(record.utime).utime)];
    EXPECT_NEAR(m.flight.roll_deg, rad_to_deg(ins.roll), 1e-5);
    EXPECT_NEAR(m.flight.pitch_deg, rad_to_deg(ins.pitch), 1e-5);
    const Eigen::Matrix3d camera = rotation_from_rpy(ins.roll, ins.pitch, ins.yaw) *
                                   turned_camera(log_->camera()).body_from_camera;
    EXPECT_LT(rotation_angle(camera_attitude_from_gimbal(m.gimbal), camera), 1e-4);
  }
}

// A 16:9 crop of a 4:3 sensor: the centre rows of the turned image, the 35 mm equivalent of the 4:3
// frame of its width in EXIF, camera.yaml for the crop; DJI's XMP calibration is the written camera.
TEST_F(ExportTest, SixteenByNineCropAndDjiCalibration) {
  PhotoExportOptions options;
  options.interval_s = 4.0;
  options.crop_16_9 = true;
  options.dji_calibration = true;
  options.model = "FC300X";
  const std::string out = dir_->file("photos_crop");
  const PhotoExportResult result = export_photos(*log_, out, options);
  const CameraModel turned = turned_camera(log_->camera());
  ASSERT_EQ(turned.width, 512);
  const int rows = 288, top = (612 - rows) / 2;  // 512 * 9 / 16
  EXPECT_EQ(result.camera.width, 512);
  EXPECT_EQ(result.camera.height, rows);
  EXPECT_DOUBLE_EQ(result.camera.fx, turned.fx);
  EXPECT_DOUBLE_EQ(result.camera.cy, turned.cy - top);
  cv::FileStorage file(result.camera_file, cv::FileStorage::READ);
  ASSERT_TRUE(file.isOpened());
  EXPECT_EQ(static_cast<int>(file["image_height"]), rows);
  cv::Mat k;
  file["camera_matrix"] >> k;
  EXPECT_NEAR(k.at<double>(1, 2), turned.cy - top, 1e-9);
  ASSERT_FALSE(result.photos.empty());
  for (const PhotoRecord& record : result.photos) {
    SCOPED_TRACE(record.file);
    const PhotoMetadata m = read_photo_metadata(out + "/" + record.file);
    EXPECT_EQ(m.model, "FC300X");
    EXPECT_EQ(m.width, 512);
    EXPECT_EQ(m.height, rows);
    // 398.79 px * 43.27 mm / 640 px (the 512x384 frame's diagonal) = 26.96 -> 27
    EXPECT_EQ(m.focal_length_35mm, 27.0);
    ASSERT_TRUE(m.has_dji_calibration);
    EXPECT_NEAR(m.calibrated_focal_px, turned.fx, 1e-6);
    EXPECT_NEAR(m.calibrated_center_x, turned.cx, 1e-6);
    EXPECT_NEAR(m.calibrated_center_y, turned.cy - top, 1e-6);
    // The pixels: the centre rows of the turned frame (up to JPEG).
    const cv::Mat photo = cv::imread(out + "/" + record.file, cv::IMREAD_GRAYSCALE);
    ASSERT_EQ(photo.cols, 512);
    ASSERT_EQ(photo.rows, rows);
    int compared = 0;
    for (const SimImageRef& ref : log_->images()) {
      if (ref.utime != record.utime) continue;
      ++compared;
      const image_t image = log_->decode_image(ref);
      const cv::Mat sim(image.height, image.width, CV_8UC1, const_cast<uint8_t*>(image.data.data()),
                        static_cast<size_t>(image.stride));
      cv::Mat diff;
      cv::absdiff(photo, turn_to_dji(sim)(cv::Rect(0, top, 512, rows)), diff);
      EXPECT_LT(cv::mean(diff)[0], 3.0);
    }
    EXPECT_EQ(compared, 1);
  }
  EXPECT_GE(result.photos.size(), 2u);
}

TEST_F(ExportTest, TurnedImageAndIntrinsicsProjectWhereTheSimulatorDoes) {
  PhotoExportOptions options;
  options.interval_s = 4.0;
  const std::string out = dir_->file("photos_projection");
  const PhotoExportResult result = export_photos(*log_, out, options);
  const CameraModel& sim = log_->camera();
  // The calibration file holds the contract's turned intrinsics.
  cv::FileStorage file(result.camera_file, cv::FileStorage::READ);
  ASSERT_TRUE(file.isOpened());
  cv::Mat k, d;
  std::vector<double> mount;
  file["camera_matrix"] >> k;
  file["distortion_coefficients"] >> d;
  file["mount_rpy_deg"] >> mount;
  EXPECT_EQ(static_cast<int>(file["image_width"]), sim.height);
  EXPECT_EQ(static_cast<int>(file["image_height"]), sim.width);
  EXPECT_DOUBLE_EQ(k.at<double>(0, 0), sim.fy);
  EXPECT_DOUBLE_EQ(k.at<double>(1, 1), sim.fx);
  EXPECT_DOUBLE_EQ(k.at<double>(0, 2), sim.cy);
  EXPECT_DOUBLE_EQ(k.at<double>(1, 2), sim.width - 1 - sim.cx);
  ASSERT_EQ(d.total(), 5u);
  EXPECT_DOUBLE_EQ(d.at<double>(0), sim.distortion[0]);
  EXPECT_DOUBLE_EQ(d.at<double>(1), sim.distortion[1]);
  EXPECT_DOUBLE_EQ(d.at<double>(2), -sim.distortion[3]);
  EXPECT_DOUBLE_EQ(d.at<double>(3), sim.distortion[2]);
  ASSERT_EQ(mount.size(), 3u);
  EXPECT_NEAR(mount[0], 0.0, 1e-9);
  EXPECT_NEAR(mount[1], 0.0, 1e-9);
  EXPECT_NEAR(mount[2], 90.0, 1e-9);

  for (const PhotoRecord& record : result.photos) {
    SCOPED_TRACE(record.file);
    const ground_truth_t& truth = log_->truth_for_frame(record.utime);
    const Eigen::Vector3d position(truth.position_ned[0], truth.position_ned[1], truth.position_ned[2]);
    const Eigen::Matrix3d world_from_sim_camera =
        rotation_from_rpy(truth.roll, truth.pitch, truth.yaw) * sim.body_from_camera;
    const PhotoMetadata m = read_photo_metadata(out + "/" + record.file);
    const Eigen::Matrix3d world_from_photo_camera = camera_attitude_from_gimbal(m.gimbal);
    // Ground points seen near the image corners and centre, 60 m below.
    std::vector<cv::Point3d> in_sim, in_photo;
    for (const cv::Point2d& n : sim.undistort({{20, 20}, {590, 30}, {300, 250}, {40, 490}, {600, 500}})) {
      const Eigen::Vector3d world = position + world_from_sim_camera * (Eigen::Vector3d(n.x, n.y, 1.0) * 60.0);
      const Eigen::Vector3d a = world_from_sim_camera.transpose() * (world - position);
      const Eigen::Vector3d b = world_from_photo_camera.transpose() * (world - position);
      in_sim.emplace_back(a.x(), a.y(), a.z());
      in_photo.emplace_back(b.x(), b.y(), b.z());
    }
    std::vector<cv::Point2d> sim_pixels, photo_pixels;
    cv::projectPoints(in_sim, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), sim.camera_matrix(), sim.distortion_coefficients(),
                      sim_pixels);
    cv::projectPoints(in_photo, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), k, d, photo_pixels);
    for (size_t i = 0; i < sim_pixels.size(); ++i) {
      const cv::Point2d expected = turned_pixel(sim_pixels[i], sim.width);
      EXPECT_NEAR(photo_pixels[i].x, expected.x, 0.05);  // 1e-4 rad of gimbal angle rounding is 0.04 px
      EXPECT_NEAR(photo_pixels[i].y, expected.y, 0.05);
    }
    // The JPEG shows the simulator's image turned: pixel (u, v) at (v, W - 1 - u).
    const cv::Mat photo = cv::imread(out + "/" + record.file, cv::IMREAD_GRAYSCALE);
    ASSERT_EQ(photo.cols, sim.height);
    ASSERT_EQ(photo.rows, sim.width);
    size_t ref_index = 0;
    while (log_->images()[ref_index].utime != record.utime) ++ref_index;
    const image_t image = log_->decode_image(log_->images()[ref_index]);
    double diff = 0, diff_unturned_flip = 0;
    int n = 0;
    for (int v = 0; v < sim.height; v += 7) {
      for (int u = 0; u < sim.width; u += 7) {
        const cv::Point2d p = turned_pixel(cv::Point2d(u, v), sim.width);
        const int sim_value = image.data[static_cast<size_t>(v * image.stride + u)];
        diff += std::abs(photo.at<uint8_t>(static_cast<int>(p.y), static_cast<int>(p.x)) - sim_value);
        // The clockwise turn (the wrong one) for contrast.
        diff_unturned_flip += std::abs(photo.at<uint8_t>(sim.width - 1 - static_cast<int>(p.y),
                                                         sim.height - 1 - static_cast<int>(p.x)) - sim_value);
        ++n;
      }
    }
    EXPECT_LT(diff / n, 3.0);
    EXPECT_GT(diff_unturned_flip / n, 10.0);
  }
}

TEST_F(ExportTest, NoPhotoInTheTurnAndTheTurnPairOverlaps) {
  PhotoExportOptions options;  // 0.5 Hz, 3 deg/s
  const PhotoExportResult result = export_photos(*log_, dir_->file("photos_turn"), options);
  EXPECT_GT(result.skipped_in_turns, 0);
  int turn_pairs = 0;
  for (const PhotoRecord& record : result.photos) {
    EXPECT_LE(std::fabs(rad_to_deg(log_->yaw_rate_at(record.utime))), 3.0);
    if (std::fabs(record.heading_change_deg) > 170.0) {
      ++turn_pairs;
      EXPECT_GT(record.overlap_with_previous, 0.2) << record.file;
    } else if (record.overlap_with_previous >= 0) {
      EXPECT_GT(record.overlap_with_previous, 0.6) << record.file;
      EXPECT_LT(record.overlap_with_previous, 0.85) << record.file;
    }
  }
  EXPECT_EQ(turn_pairs, 1);
}

// North, east (m) of `b` from `a` on the WGS84 ellipsoid: one step at a's altitude.
Eigen::Vector2d gps_offset(const PhotoMetadata& a, const PhotoMetadata& b) {
  GeodeticTrack track({a.latitude_deg, a.longitude_deg, a.altitude_m});
  return track.ned({b.latitude_deg, b.longitude_deg, a.altitude_m}).head<2>();
}

// The photos alone (JPEG pixels, camera.yaml, GPS, gimbal angles, relative
// altitude) explain the image motion between consecutive photos, on the
// lines and across the 180 deg turn: ORB matches (homography-consistent)
// land where the metadata put their ground points, to a few pixels.
TEST_F(ExportTest, MetadataExplainsTheImageMotionBetweenPhotos) {
  const std::string out = dir_->file("photos_motion");
  const PhotoExportResult result = export_photos(*log_, out, PhotoExportOptions());
  cv::FileStorage file(result.camera_file, cv::FileStorage::READ);
  cv::Mat k, d;
  file["camera_matrix"] >> k;
  file["distortion_coefficients"] >> d;
  const cv::Ptr<cv::ORB> orb = cv::ORB::create(1500);
  const cv::BFMatcher matcher(cv::NORM_HAMMING, true);
  bool saw_turn = false;
  for (size_t i = 1; i < result.photos.size(); ++i) {
    SCOPED_TRACE(result.photos[i].file);
    const PhotoMetadata a = read_photo_metadata(out + "/" + result.photos[i - 1].file);
    const PhotoMetadata b = read_photo_metadata(out + "/" + result.photos[i].file);
    std::vector<cv::KeyPoint> ka, kb;
    cv::Mat da, db;
    orb->detectAndCompute(cv::imread(out + "/" + result.photos[i - 1].file, cv::IMREAD_GRAYSCALE), cv::noArray(), ka, da);
    orb->detectAndCompute(cv::imread(out + "/" + result.photos[i].file, cv::IMREAD_GRAYSCALE), cv::noArray(), kb, db);
    std::vector<cv::DMatch> matches;
    matcher.match(da, db, matches);
    std::vector<cv::Point2f> pa, pb;
    for (const cv::DMatch& m : matches) {
      pa.push_back(ka[static_cast<size_t>(m.queryIdx)].pt);
      pb.push_back(kb[static_cast<size_t>(m.trainIdx)].pt);
    }
    ASSERT_GE(pa.size(), 8u);
    std::vector<uchar> inlier;
    cv::findHomography(pa, pb, cv::RANSAC, 4.0, inlier);
    // A's ground points: rays from A's pose to the ground plane below A
    // (height above ground = relative altitude - terrain at the take-off datum, from the truth).
    const ground_truth_t& truth_a = log_->truth_for_frame(result.photos[i - 1].utime);
    const double ground_z = -truth_a.terrain_height_m;
    const Eigen::Matrix3d ra = camera_attitude_from_gimbal(a.gimbal), rb = camera_attitude_from_gimbal(b.gimbal);
    const Eigen::Vector3d pos_a(0, 0, -a.relative_altitude_m);
    const Eigen::Vector2d ne = gps_offset(a, b);
    const Eigen::Vector3d pos_b(ne.x(), ne.y(), -b.relative_altitude_m);
    std::vector<cv::Point2f> used_a, used_b;
    for (size_t j = 0; j < pa.size(); ++j) {
      if (inlier[j]) {
        used_a.push_back(pa[j]);
        used_b.push_back(pb[j]);
      }
    }
    ASSERT_GE(used_a.size(), 30u);
    std::vector<cv::Point2f> rays;
    cv::undistortPoints(used_a, rays, k, d);
    std::vector<cv::Point3d> in_b;
    for (const cv::Point2f& n : rays) {
      const Eigen::Vector3d ray = ra * Eigen::Vector3d(n.x, n.y, 1.0);
      const Eigen::Vector3d ground = pos_a + ray * ((ground_z - pos_a.z()) / ray.z());
      const Eigen::Vector3d c = rb.transpose() * (ground - pos_b);
      in_b.emplace_back(c.x(), c.y(), c.z());
    }
    std::vector<cv::Point2d> predicted;
    cv::projectPoints(in_b, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), k, d, predicted);
    std::vector<double> errors;
    for (size_t j = 0; j < predicted.size(); ++j) errors.push_back(cv::norm(predicted[j] - cv::Point2d(used_b[j])));
    EXPECT_LT(median(errors, EvenMedian::kUpper), 3.0) << used_a.size() << " matches";
    if (std::fabs(result.photos[i].heading_change_deg) > 170.0) saw_turn = true;
  }
  EXPECT_TRUE(saw_turn);
}

// One SRT block: index, times, "FrameCnt: N, DiffTime: Dms", date-time, fields.
struct SrtBlock {
  int index = 0;
  std::string times, counter, when, fields;
};

std::vector<SrtBlock> read_srt(const std::string& path) {
  std::ifstream in(path);
  std::vector<SrtBlock> blocks;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    SrtBlock b;
    b.index = std::stoi(line);
    std::getline(in, b.times);
    std::getline(in, b.counter);
    std::getline(in, b.when);
    std::getline(in, b.fields);
    blocks.push_back(b);
  }
  return blocks;
}

double srt_field(const std::string& fields, const std::string& name) {
  const std::regex pattern("\\b" + name + ": ([-+0-9.]+)");
  std::smatch match;
  if (!std::regex_search(fields, match, pattern)) throw std::runtime_error("no " + name + " in " + fields);
  return std::stod(match[1]);
}

TEST_F(ExportTest, VideoSrtAndCsvParseBack) {
  VideoExportOptions options;
  options.every = 2;
  const std::string video = dir_->file("flight.avi"), srt = dir_->file("flight.SRT"), csv = dir_->file("flight.csv");
  const VideoExportResult result = export_video(*log_, video, srt, csv, options);
  const size_t expected_frames = (log_->images().size() + 1) / 2;
  ASSERT_EQ(result.frames, static_cast<int64_t>(expected_frames));
  EXPECT_NEAR(result.fps, 2.0, 1e-9);
  EXPECT_EQ(result.frames_with_range, result.frames);

  const std::vector<SrtBlock> blocks = read_srt(srt);
  ASSERT_EQ(blocks.size(), expected_frames);
  const CameraModel turned = turned_camera(log_->camera());
  const std::regex times(R"((\d\d):(\d\d):(\d\d),(\d\d\d) --> (\d\d):(\d\d):(\d\d),(\d\d\d))");
  const std::regex counter(R"(FrameCnt: (\d+), DiffTime: (\d+)ms)");
  for (size_t i = 0; i < blocks.size(); ++i) {
    SCOPED_TRACE("SRT block " + std::to_string(i + 1));
    const SrtBlock& b = blocks[i];
    const SimImageRef& ref = log_->images()[2 * i];
    EXPECT_EQ(b.index, static_cast<int>(i + 1));
    std::smatch t, c;
    ASSERT_TRUE(std::regex_match(b.times, t, times)) << b.times;
    const int64_t start_ms = std::stoll(t[1]) * 3600000 + std::stoll(t[2]) * 60000 + std::stoll(t[3]) * 1000 + std::stoll(t[4]);
    EXPECT_NEAR(start_ms, (ref.utime - log_->images().front().utime) * 1e-3, 1.0);
    ASSERT_TRUE(std::regex_match(b.counter, c, counter)) << b.counter;
    EXPECT_EQ(std::stoi(c[1]), static_cast<int>(i + 1));
    if (i > 0) {  // 500 ms, or more after a dropped frame
      EXPECT_NEAR(std::stoi(c[2]), (ref.utime - log_->images()[2 * i - 2].utime) * 1e-3, 1.0);
    }
    EXPECT_EQ(b.when, srt_date_time(ref.utime));
    const ground_truth_t& truth = log_->truth_for_frame(ref.utime);
    const DjiAngles gimbal{srt_field(b.fields, "gb_roll"), srt_field(b.fields, "gb_pitch"), srt_field(b.fields, "gb_yaw")};
    const Eigen::Matrix3d truth_camera = rotation_from_rpy(truth.roll, truth.pitch, truth.yaw) * turned.body_from_camera;
    EXPECT_LT(rotation_angle(camera_attitude_from_gimbal(gimbal), truth_camera), 1e-4);
    EXPECT_NEAR(srt_field(b.fields, "flight_roll"), rad_to_deg(truth.roll), 1e-5);
    EXPECT_NEAR(srt_field(b.fields, "rel_alt"), -truth.position_ned[2], 1e-3);
    EXPECT_NEAR(srt_field(b.fields, "abs_alt"), 300.0 - truth.position_ned[2], 1e-3);
    EXPECT_NEAR(srt_field(b.fields, "latitude"), 40.4406 + truth.position_ned[0] / 111035.0, 2e-6);
    // Slant range along the optical axis (body z): height / (cos roll cos pitch) over gentle relief.
    EXPECT_NEAR(srt_field(b.fields, "range"), truth.height_agl_m / (std::cos(truth.roll) * std::cos(truth.pitch)), 2.0);
  }

  std::ifstream csv_in(csv);
  std::string header;
  std::getline(csv_in, header);
  EXPECT_EQ(header, "time_s,roll_deg,pitch_deg,yaw_deg,height_m,lat_deg,lon_deg,alt_m");
  std::string row;
  size_t rows = 0;
  while (std::getline(csv_in, row)) {
    std::stringstream fields(row);
    std::vector<double> v;
    for (std::string cell; std::getline(fields, cell, ',');) v.push_back(std::stod(cell));
    ASSERT_EQ(v.size(), 8u) << row;
    const SimImageRef& ref = log_->images()[2 * rows];
    const ground_truth_t& truth = log_->truth_for_frame(ref.utime);
    EXPECT_NEAR(v[0], (ref.utime - log_->images().front().utime) * 1e-6, 1e-6);
    EXPECT_NEAR(v[1], rad_to_deg(truth.roll), 1e-5);
    EXPECT_NEAR(v[4], -truth.position_ned[2], 1e-3);
    ++rows;
  }
  EXPECT_EQ(rows, expected_frames);

  cv::VideoCapture capture(video, cv::CAP_OPENCV_MJPEG);
  ASSERT_TRUE(capture.isOpened());
  EXPECT_EQ(static_cast<int>(capture.get(cv::CAP_PROP_FRAME_COUNT)), static_cast<int>(expected_frames));
  cv::Mat frame;
  ASSERT_TRUE(capture.read(frame));
  ASSERT_EQ(frame.cols, turned.width);
  ASSERT_EQ(frame.rows, turned.height);
  cv::Mat grey;
  cv::extractChannel(frame, grey, 0);
  const image_t first = log_->decode_image(log_->images().front());
  const cv::Mat expected = turn_to_dji(cv::Mat(first.height, first.width, CV_8UC1, const_cast<uint8_t*>(first.data.data())));
  EXPECT_LT(cv::norm(grey, expected, cv::NORM_L1) / static_cast<double>(grey.total()), 3.0);
}

// SimLog::load(path) fails with a message naming the file and saying `what`.
void expect_load_error(const std::string& path, const std::string& what) {
  try {
    SimLog::load(path);
    ADD_FAILURE() << path << ": no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
  }
}

TEST(ExportInput, NotASimLogNamesTheFile) {
  testing::TempDir dir("export_bad");
  const std::string garbage = dir.file("garbage.lcmlog");
  testing::write_file_bytes(garbage, std::vector<uint8_t>(4096, 0x5a));
  expect_load_error(garbage, "no CONFIG");
  expect_load_error(dir.file("missing.lcmlog"), "");
}

TEST(ExportInput, ConfigWithoutCameraOrFromAnotherProcess) {
  testing::TempDir dir("export_config");
  auto write_config = [&](const std::string& path, const std::string& name, const std::string& yaml) {
    LogWriter writer(path);
    config_t config;
    config.utime = 1;
    config.name = name;
    config.source = "test";
    config.yaml = yaml;
    std::vector<uint8_t> bytes(static_cast<size_t>(config.getEncodedSize()));
    config.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
    writer.write(1, channels::kConfig, bytes.data(), bytes.size());
  };
  const std::string no_camera = dir.file("no_camera.lcmlog");
  write_config(no_camera, "sim", "name: sim\nseed: 1\n");
  expect_load_error(no_camera, "no camera");
  const std::string replay = dir.file("replay.lcmlog");
  write_config(replay, "replay", "name: replay\n");
  expect_load_error(replay, "no CONFIG record from nadir_sim, only from 'replay'");
}

TEST(ExportOptions, CheckNamesTheOption) {
  PhotoExportOptions photo;
  photo.interval_s = 0.0;
  try {
    photo.Check();
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("--interval"), std::string::npos);
  }
  photo = PhotoExportOptions();
  photo.quality = 101;
  EXPECT_THROW(photo.Check(), std::invalid_argument);
  VideoExportOptions video;
  video.every = 0;
  EXPECT_THROW(video.Check(), std::invalid_argument);
  EXPECT_THROW(parse_attitude_source("gps"), std::invalid_argument);
}

TEST(DjiOrientation, NadirLevelFlightNorthIsPitchMinus90YawZero) {
  // Level, heading north: the gimbal looks straight down, image top = north.
  const CameraModel turned = turned_camera(CameraModel{612, 512, 398.79, 398.79, 305.5, 255.5, {0, 0, 0, 0, 0}});
  const DjiAngles a = gimbal_angles(turned.body_from_camera, 0.0);
  EXPECT_LT(rotation_angle(camera_attitude_from_gimbal(a), turned.body_from_camera), 1e-9);
  EXPECT_NEAR(a.pitch_deg, -90.0, 1e-6);
  // Image top is forward: the turned camera's -y axis is body forward.
  EXPECT_NEAR((turned.body_from_camera * Eigen::Vector3d(0, -1, 0) - Eigen::Vector3d(1, 0, 0)).norm(), 0.0, 1e-12);
}

}  // namespace
}  // namespace nadir::exporter
