#include "processes/sim/flight_profile.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <stdexcept>

#include <yaml-cpp/yaml.h>

#include "common/paths.h"
#include "processes/sim/sim_rotation.h"

namespace nadir::sim {
namespace {

constexpr double kGravity = 9.80665;

FlightLeg parse_leg(const Config& c) {
  FlightLeg leg;
  const std::string type = c.get<std::string>("type");
  if (type == "straight") {
    c.require_known_keys({"type", "distance_m"});
    leg.type = FlightLeg::kStraight;
    leg.distance_m = c.has("distance_m") ? c.get_in_range<double>("distance_m", 0.0, 1.0, 1e6) : -1.0;
  } else if (type == "turn") {
    c.require_known_keys({"type", "angle_deg", "bank_deg"});
    leg.type = FlightLeg::kTurn;
    leg.angle_deg = c.get<double>("angle_deg");
    c.check_range("angle_deg", leg.angle_deg, -720.0, 720.0);
    if (std::fabs(leg.angle_deg) < 1.0) throw c.error("angle_deg", "must be at least 1 degree in magnitude");
    leg.bank_deg = c.get_in_range<double>("bank_deg", 15.0, 1.0, 35.0);
  } else if (type == "climb") {
    c.require_known_keys({"type", "distance_m", "delta_alt_m"});
    leg.type = FlightLeg::kClimb;
    leg.distance_m = c.get_in_range<double>("distance_m", 0.0, 10.0, 1e6);
    leg.delta_alt_m = c.get<double>("delta_alt_m");
    c.check_range("delta_alt_m", leg.delta_alt_m, -500.0, 500.0);
  } else {
    throw c.error("type", "= '" + type + "' is not one of straight, turn, climb");
  }
  return leg;
}

// terrain.featureless: a list of boxes; the ranges are checked by
// FeaturelessArea::Check (one place for the rules).
std::vector<FeaturelessArea> parse_featureless(const Config& terrain) {
  std::vector<FeaturelessArea> areas;
  const YAML::Node list = terrain.node()["featureless"];
  if (!list || list.IsNull()) return areas;
  if (!list.IsSequence())
    throw terrain.error("featureless", "must be a list of {north_m: [min, max], east_m: [min, max], contrast: C}");
  for (size_t i = 0; i < list.size(); ++i) {
    const Config a(list[i], terrain.source(), terrain.key_path("featureless") + "[" + std::to_string(i) + "]");
    a.require_known_keys({"north_m", "east_m", "contrast", "shore_m", "albedo"});
    auto min_max = [&](const std::string& key) {
      const std::vector<double> v = a.get<std::vector<double>>(key);
      if (v.size() != 2) throw a.error(key, "must be [min, max] (two numbers)");
      return v;
    };
    FeaturelessArea area;
    const std::vector<double> north = min_max("north_m"), east = min_max("east_m");
    area.north_min_m = north[0];
    area.north_max_m = north[1];
    area.east_min_m = east[0];
    area.east_max_m = east[1];
    area.contrast = a.get<double>("contrast");
    area.shore_m = a.get<double>("shore_m", area.shore_m);
    area.albedo = a.get<double>("albedo", area.albedo);
    areas.push_back(area);
  }
  return areas;
}

// A world file named in the profile: relative paths are relative to the
// profile file's folder.
std::string world_path(const Config& world, const std::string& key) {
  const std::string file = world.get<std::string>(key);
  if (file.empty()) throw world.error(key, "must name a GeoTIFF file");
  const std::filesystem::path path(file);
  if (path.is_absolute()) return file;
  const std::filesystem::path folder = std::filesystem::path(world.source()).parent_path();
  return (folder / path).lexically_normal().string();
}

}  // namespace

std::string FlightProfile::resolve(const std::string& name_or_path) {
  if (name_or_path.find('/') != std::string::npos ||
      (name_or_path.size() > 5 && name_or_path.compare(name_or_path.size() - 5, 5, ".yaml") == 0))
    return name_or_path;
  return checkout_root() + "/config/profiles/" + name_or_path + ".yaml";
}

namespace {

// Sets `path` (one or two keys) of the profile's YAML text to `value`.
std::string with_value(const std::string& yaml, const std::vector<std::string>& path, double value) {
  YAML::Node node = YAML::Load(yaml);
  if (path.size() == 1) {
    node[path[0]] = value;
  } else {
    node[path[0]][path[1]] = value;
  }
  YAML::Emitter out;
  out << node;
  return std::string(out.c_str()) + "\n";
}

void require_override_range(const std::string& source, const std::string& key, double value, double lo, double hi) {
  if (value >= lo && value <= hi) return;
  std::ostringstream text;
  text << source << ": " << key << " override " << value << " outside [" << lo << ", " << hi << "]";
  throw ConfigError(text.str());
}

}  // namespace

void FlightProfile::override_relief_scale(double relief_scale) {
  require_override_range(source, "terrain.relief_scale", relief_scale, 0.0, 3.0);
  terrain.relief_scale = relief_scale;
  yaml = with_value(yaml, {"terrain", "relief_scale"}, relief_scale);
  overrides.push_back("terrain.relief_scale");
}

void FlightProfile::override_altitude_agl(double altitude_agl) {
  require_override_range(source, "altitude_agl_m", altitude_agl, 30.0, 3000.0);
  altitude_agl_m = altitude_agl;
  yaml = with_value(yaml, {"altitude_agl_m"}, altitude_agl);
  overrides.push_back("altitude_agl_m");
}

FlightProfile FlightProfile::load(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw ConfigError(path + ": cannot open flight profile");
  std::stringstream text;
  text << in.rdbuf();
  return parse(text.str(), path);
}

FlightProfile FlightProfile::parse(const std::string& yaml_text, const std::string& source) {
  const Config c = Config::parse(yaml_text, source);
  FlightProfile p;
  p.source = source;
  p.yaml = yaml_text;
  c.require_known_keys({"name", "distance_m", "speed_mps", "altitude_agl_m", "initial_heading_deg", "pitch_trim_deg",
                        "oscillation", "reference", "terrain", "world", "legs"});
  p.name = c.get<std::string>("name");
  p.distance_m = c.get_in_range<double>("distance_m", p.distance_m, 10.0, 1e6);
  p.speed_mps = c.get_in_range<double>("speed_mps", p.speed_mps, 1.0, 100.0);
  p.altitude_agl_m = c.get_in_range<double>("altitude_agl_m", p.altitude_agl_m, 30.0, 3000.0);
  p.initial_heading_deg = c.get_in_range<double>("initial_heading_deg", 0.0, -360.0, 360.0);
  p.pitch_trim_deg = c.get_in_range<double>("pitch_trim_deg", p.pitch_trim_deg, -15.0, 15.0);
  const Config osc = c.section_or_empty("oscillation");
  osc.require_known_keys({"roll_deg", "pitch_deg", "yaw_deg"});
  p.roll_oscillation_deg = osc.get_in_range<double>("roll_deg", p.roll_oscillation_deg, 0.0, 10.0);
  p.pitch_oscillation_deg = osc.get_in_range<double>("pitch_deg", p.pitch_oscillation_deg, 0.0, 10.0);
  p.yaw_oscillation_deg = osc.get_in_range<double>("yaw_deg", p.yaw_oscillation_deg, 0.0, 10.0);
  const Config ref = c.section_or_empty("reference");
  ref.require_known_keys({"latitude_deg", "longitude_deg", "height_m"});
  p.reference_latitude_deg = ref.get_in_range<double>("latitude_deg", p.reference_latitude_deg, -85.0, 85.0);
  p.reference_longitude_deg = ref.get_in_range<double>("longitude_deg", p.reference_longitude_deg, -180.0, 180.0);
  p.reference_height_m = ref.get_in_range<double>("height_m", p.reference_height_m, -500.0, 9000.0);
  if (c.has("world")) {
    const Config world = c.section("world");
    world.require_known_keys({"orthophoto", "dem"});
    p.world_orthophoto = world_path(world, "orthophoto");
    p.world_dem = world_path(world, "dem");
    for (const char* key : {"latitude_deg", "longitude_deg"})
      if (!ref.has(key)) throw ref.error(key, "is required with world: (where on its rasters the flight starts)");
    if (ref.has("height_m"))
      throw ref.error("height_m", "must not be given with world: (the datum is the DEM's height at the reference point)");
  }
  const Config terrain = c.section_or_empty("terrain");
  terrain.require_known_keys({"relief_scale", "featureless"});
  p.terrain.relief_scale = terrain.get_in_range<double>("relief_scale", 1.0, 0.0, 3.0);
  p.terrain.featureless = parse_featureless(terrain);
  try {
    p.terrain.Check();
  } catch (const std::invalid_argument& e) {
    throw ConfigError(source + ": " + e.what());
  }

  const YAML::Node legs = c.node()["legs"];
  if (!legs || !legs.IsSequence() || legs.size() == 0) throw c.error("legs", "must be a non-empty list of legs");
  int rest_legs = 0;
  double fixed = 0.0;
  for (size_t i = 0; i < legs.size(); ++i) {
    const Config leg_config(legs[i], source, c.key_path("legs") + "[" + std::to_string(i) + "]");
    if (!legs[i].IsMap()) throw leg_config.error("type", "leg must be a map with a type");
    FlightLeg leg = parse_leg(leg_config);
    if (leg.type == FlightLeg::kTurn) {
      const double rate = kGravity * std::tan(deg2rad(leg.bank_deg)) / p.speed_mps;
      fixed += p.speed_mps * 2.0 * std::fabs(deg2rad(leg.angle_deg)) / rate;
    } else if (leg.distance_m < 0) {
      ++rest_legs;
    } else {
      fixed += leg.distance_m;
    }
    p.legs.push_back(leg);
  }
  if (rest_legs > 1) throw c.error("legs", "only one straight leg may omit distance_m (it takes the rest)");
  const double rest = p.distance_m - fixed;
  if (rest_legs == 1) {
    if (rest < 1.0) {
      std::ostringstream text;
      text << "sum to " << fixed << " m before the open straight leg, more than distance_m = " << p.distance_m;
      throw c.error("legs", text.str());
    }
    for (FlightLeg& leg : p.legs)
      if (leg.type == FlightLeg::kStraight && leg.distance_m < 0) leg.distance_m = rest;
  } else if (std::fabs(rest) > 1.0) {
    std::ostringstream text;
    text << "sum to " << fixed << " m but distance_m = " << p.distance_m << " (give one straight leg no distance_m)";
    throw c.error("legs", text.str());
  }
  return p;
}

Eigen::Matrix3d TruthState::world_from_body() const { return sim::world_from_body(roll, pitch, yaw); }

Trajectory::Trajectory(const FlightProfile& profile, uint64_t seed) {
  speed_ = profile.speed_mps;
  pitch_trim_ = deg2rad(profile.pitch_trim_deg);
  double t = 0.0, heading = deg2rad(profile.initial_heading_deg), alt = profile.altitude_agl_m;
  for (const FlightLeg& leg : profile.legs) {
    LegSpan span{leg.type, t, 0.0, heading, alt, 0.0, 0.0};
    if (leg.type == FlightLeg::kTurn) {
      span.turn_angle = deg2rad(leg.angle_deg);
      const double rate = kGravity * std::tan(deg2rad(leg.bank_deg)) / speed_;
      span.duration = 2.0 * std::fabs(span.turn_angle) / rate;
      heading += span.turn_angle;
    } else {
      span.duration = leg.distance_m / speed_;
      if (leg.type == FlightLeg::kClimb) {
        span.delta_alt = leg.delta_alt_m;
        alt += leg.delta_alt_m;
      }
    }
    legs_.push_back(span);
    t += span.duration;
  }
  duration_ = t;

  // Seeded attitude oscillations: three sinusoids per axis, 0.07-0.6 Hz,
  // scaled so each axis has the configured RMS.
  std::mt19937_64 rng(seed ^ 0x51a7e5eedULL);
  auto make = [&](double rms_deg) {
    std::vector<Sinusoid> s;
    for (int i = 0; i < 3; ++i) {
      const double f = 0.07 + 0.53 * ((rng() >> 11) * (1.0 / 9007199254740992.0));
      const double phase = 2.0 * M_PI * ((rng() >> 11) * (1.0 / 9007199254740992.0));
      s.push_back({deg2rad(rms_deg) * std::sqrt(2.0 / 3.0), 2.0 * M_PI * f, phase});
    }
    return s;
  };
  roll_osc_ = make(profile.roll_oscillation_deg);
  pitch_osc_ = make(profile.pitch_oscillation_deg);
  yaw_osc_ = make(profile.yaw_oscillation_deg);

  const size_t n = static_cast<size_t>(std::ceil(duration_ / key_dt_)) + 2;
  keys_.resize(n);
  keys_[0] = Eigen::Vector2d::Zero();
  for (size_t k = 1; k < n; ++k) keys_[k] = keys_[k - 1] + integrate((k - 1) * key_dt_, k * key_dt_);
}

const Trajectory::LegSpan& Trajectory::leg_at(double t) const {
  for (size_t i = 0; i + 1 < legs_.size(); ++i)
    if (t < legs_[i + 1].t0) return legs_[i];
  return legs_.back();
}

double Trajectory::heading(double t, double* rate) const {
  const LegSpan& leg = leg_at(t);
  double tau = std::min(std::max(t - leg.t0, 0.0), leg.duration);
  if (leg.type != FlightLeg::kTurn) {
    if (rate) *rate = 0.0;
    return leg.heading0;
  }
  const double T = leg.duration, w = 2.0 * M_PI / T;
  const double r_max = 2.0 * leg.turn_angle / T;
  if (rate) *rate = (t - leg.t0 > T) ? 0.0 : r_max * 0.5 * (1.0 - std::cos(w * tau));
  return leg.heading0 + r_max * (0.5 * tau - std::sin(w * tau) / (2.0 * w));
}

double Trajectory::altitude(double t, double* climb_rate) const {
  const LegSpan& leg = leg_at(t);
  const double tau = std::min(std::max(t - leg.t0, 0.0), leg.duration);
  if (leg.type != FlightLeg::kClimb) {
    if (climb_rate) *climb_rate = 0.0;
    return leg.altitude0;
  }
  const double T = leg.duration, w = 2.0 * M_PI / T;
  if (climb_rate) *climb_rate = (t - leg.t0 > T) ? 0.0 : leg.delta_alt / T * (1.0 - std::cos(w * tau));
  return leg.altitude0 + leg.delta_alt / T * (tau - std::sin(w * tau) / w);
}

Eigen::Vector2d Trajectory::horizontal_velocity(double t) const {
  const double psi = heading(t, nullptr);
  return speed_ * Eigen::Vector2d(std::cos(psi), std::sin(psi));
}

// Composite Simpson over [t0, t1]; the heading is smooth, so 8 panels per
// 0.1 s leave errors far below a millimetre.
Eigen::Vector2d Trajectory::integrate(double t0, double t1) const {
  const int n = 8;
  const double h = (t1 - t0) / n;
  if (h == 0.0) return Eigen::Vector2d::Zero();
  Eigen::Vector2d sum = horizontal_velocity(t0) + horizontal_velocity(t1);
  for (int i = 1; i < n; ++i) sum += (i % 2 ? 4.0 : 2.0) * horizontal_velocity(t0 + i * h);
  return sum * (h / 3.0);
}

double Trajectory::oscillation(const std::vector<Sinusoid>& s, double t) {
  double v = 0.0;
  for (const Sinusoid& x : s) v += x.amplitude * std::sin(x.omega * t + x.phase);
  return v;
}

void Trajectory::attitude(double t, double* roll, double* pitch, double* yaw) const {
  double rate = 0.0, climb = 0.0;
  const double psi = heading(t, &rate);
  altitude(t, &climb);
  *roll = std::atan(speed_ * rate / kGravity) + oscillation(roll_osc_, t);
  *pitch = pitch_trim_ + 0.3 * std::atan(climb / speed_) + oscillation(pitch_osc_, t);
  *yaw = wrap_pi(psi + oscillation(yaw_osc_, t));
}

TruthState Trajectory::at(double t) const {
  TruthState s;
  s.t = t;
  const double tc = std::min(std::max(t, 0.0), duration_ + 1.0);
  const size_t k = std::min(static_cast<size_t>(tc / key_dt_), keys_.size() - 1);
  const Eigen::Vector2d ne = keys_[k] + integrate(k * key_dt_, tc);
  double climb = 0.0;
  const double alt = altitude(tc, &climb);
  s.position_ned = Eigen::Vector3d(ne.x(), ne.y(), -alt);
  const Eigen::Vector2d v = horizontal_velocity(tc);
  s.velocity_ned = Eigen::Vector3d(v.x(), v.y(), -climb);
  attitude(tc, &s.roll, &s.pitch, &s.yaw);
  // Body rates from the attitude's derivative: [w]x = R^T dR/dt.
  const double h = 1e-3;
  double r0, p0, y0, r1, p1, y1;
  attitude(tc - h, &r0, &p0, &y0);
  attitude(tc + h, &r1, &p1, &y1);
  const Eigen::Matrix3d R = s.world_from_body();
  const Eigen::Matrix3d dR = (sim::world_from_body(r1, p1, y1) - sim::world_from_body(r0, p0, y0)) / (2.0 * h);
  const Eigen::Matrix3d W = R.transpose() * dR;
  s.angular_rate_body = Eigen::Vector3d(0.5 * (W(2, 1) - W(1, 2)), 0.5 * (W(0, 2) - W(2, 0)), 0.5 * (W(1, 0) - W(0, 1)));
  return s;
}

}  // namespace nadir::sim
