#include "tools/track_truth/sim_scene.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <vector>

#include "common/config.h"
#include "processes/sim/flight_profile.h"
#include "processes/sim/ray_caster.h"
#include "processes/sim/sensor_options.h"
#include "processes/sim/sim_rotation.h"
#include "processes/sim/simulator.h"

namespace nadir::track_truth {

namespace {

struct Parsed {
  uint64_t seed = 0;
  sim::TerrainOptions terrain;
  sim::SimCamera camera;
  sim::SensorOptions sensors;
};

// The sensor set the simulator ran with: CONFIG holds its effective values
// under `sensors:` (with `set:` naming it); SensorOptions reads a set by name.
sim::SensorOptions sensors_of(const Config& root, const std::string& source) {
  YAML::Node sensors = YAML::Load(root.section("sensors").dump());
  const std::string set = sensors["set"] ? sensors["set"].as<std::string>() : std::string("sensors");
  sensors.remove("set");
  YAML::Node wrapped;
  wrapped[set] = sensors;
  YAML::Emitter out;
  out << wrapped;
  return sim::SensorOptions::from_config(Config::parse(out.c_str(), source + " (sensors)"), set);
}

Parsed parse(const std::string& config_yaml, const std::string& source) {
  const Config root = Config::parse(config_yaml, source);
  if (root.get<std::string>("name", "") != "sim")
    throw root.error("name", "is not 'sim': the CONFIG of nadir_sim is needed (the world the log was flown in)");
  Parsed p;
  p.seed = root.get<uint64_t>("seed");
  const sim::FlightProfile profile = sim::FlightProfile::parse(root.section("profile").dump(), source + " (profile)");
  p.terrain = profile.terrain;
  p.terrain.seed = p.seed;  // as the simulator does
  p.sensors = sensors_of(root, source);
  p.camera = sim::true_camera(sim::SimCamera::from_config(root), p.sensors.camera);
  return p;
}

}  // namespace

SimScene::SimScene(const std::string& config_yaml, const std::string& source) {
  const Parsed p = parse(config_yaml, source);
  seed_ = p.seed;
  relief_scale_ = p.terrain.relief_scale;
  terrain_ = std::make_unique<const sim::Terrain>(p.terrain);
  camera_ = p.camera;
  const auto& lever = p.sensors.camera.lever_arm_m;
  lever_arm_body_ = Eigen::Vector3d(lever[0], lever[1], lever[2]);
  exposure_delay_us_ = std::llround(p.sensors.camera.exposure_delay_us());
  match_window_us_ = std::llround(0.25e6 / p.camera.rate_hz);
}

void SimScene::add_truth(const ground_truth_t& truth) {
  if (truth.kind != ground_truth_t::KIND_FRAME) return;
  const Eigen::Matrix3d world_from_body = sim::world_from_body(truth.roll, truth.pitch, truth.yaw);
  CameraPose pose;
  pose.centre = Eigen::Vector3d(truth.position_ned[0], truth.position_ned[1], truth.position_ned[2]) +
                world_from_body * lever_arm_body_;
  pose.world_from_camera = world_from_body * camera_.body_from_camera;
  frames_[truth.utime] = pose;
}

bool SimScene::pose_at(int64_t utime, CameraPose* pose) const {
  const int64_t exposure = utime + exposure_delay_us_;
  auto after = frames_.lower_bound(exposure);
  auto best = frames_.end();
  if (after != frames_.end()) best = after;
  if (after != frames_.begin()) {
    auto before = std::prev(after);
    if (best == frames_.end() || exposure - before->first < best->first - exposure) best = before;
  }
  if (best == frames_.end() || std::llabs(best->first - exposure) > match_window_us_) return false;
  *pose = best->second;
  return true;
}

bool SimScene::ground_point(const CameraPose& pose, const Eigen::Vector2d& px, Eigen::Vector3d* point) const {
  const std::vector<cv::Point2d> n = camera_.undistort({cv::Point2d(px.x(), px.y())});
  const Eigen::Vector3d dir = (pose.world_from_camera * Eigen::Vector3d(n[0].x, n[0].y, 1.0)).normalized();
  sim::RayHit hit;
  if (!sim::cast_ray(*terrain_, pose.centre, dir, -1.0, &hit)) return false;
  *point = pose.centre + hit.t * dir;
  return true;
}

bool SimScene::pixel_of(const CameraPose& pose, const Eigen::Vector3d& point, Eigen::Vector2d* px) const {
  const Eigen::Vector3d c = pose.world_from_camera.transpose() * (point - pose.centre);
  if (!(c.z() > 1e-6)) return false;
  const std::vector<cv::Point2d> p = camera_.project({cv::Point3d(c.x(), c.y(), c.z())});
  *px = Eigen::Vector2d(p[0].x, p[0].y);
  return std::isfinite(px->x()) && std::isfinite(px->y());
}

bool SimScene::visible(const CameraPose& pose, const Eigen::Vector3d& point) const {
  const Eigen::Vector3d to = point - pose.centre;
  const double distance = to.norm();
  sim::RayHit hit;
  if (!sim::cast_ray(*terrain_, pose.centre, to / distance, -1.0, &hit)) return false;
  return hit.t > distance - 0.05;  // the first hit is the point itself (5 cm of the ray solver's tolerance)
}

}  // namespace nadir::track_truth
