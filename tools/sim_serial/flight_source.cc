#include "tools/sim_serial/flight_source.h"

#include <Eigen/Core>

#include <cmath>
#include <random>

#include "common/channels.h"
#include "common/geodetic.h"
#include "common/geometry.h"
#include "common/log_file.h"

namespace nadir::sim_serial {
namespace {

class LogSource : public FlightSource {
 public:
  explicit LogSource(const std::string& path) : reader_(path) {}

  bool next(Sample* sample) override {
    LogEvent event;
    while (reader_.next(&event)) {
      if (event.channel == channels::kIns) {
        sample->kind = Sample::Kind::kIns;
        if (sample->ins.decode(event.data, 0, static_cast<int>(event.size)) != static_cast<int>(event.size)) {
          ++undecodable_;
          continue;
        }
        sample->t_us = sample->ins.utime;
        return true;
      }
      if (event.channel == channels::kAltimeter) {
        sample->kind = Sample::Kind::kAltimeter;
        if (sample->altimeter.decode(event.data, 0, static_cast<int>(event.size)) != static_cast<int>(event.size)) {
          ++undecodable_;
          continue;
        }
        sample->t_us = sample->altimeter.utime;
        return true;
      }
    }
    return false;
  }

  std::string describe() const override {
    std::string text = "log " + reader_.path();
    if (undecodable_ > 0) text += ", " + std::to_string(undecodable_) + " undecodable messages skipped";
    if (reader_.corrupt_records() > 0) text += "\n" + reader_.damage_report();
    return text;
  }

 private:
  LogReader reader_;
  int64_t undecodable_ = 0;
};

class GeneratedSource : public FlightSource {
 public:
  explicit GeneratedSource(const GeneratedFlightOptions& o)
      : o_(o), track_({o.latitude_deg, o.longitude_deg, 0.0}), rng_(o.seed) {}

  bool next(Sample* sample) override {
    const int64_t ins_period = static_cast<int64_t>(1e6 / o_.ins_rate_hz);
    const int64_t alt_period = static_cast<int64_t>(1e6 / o_.altimeter_rate_hz);
    const int64_t t_ins = ins_index_ * ins_period;
    const int64_t t_alt = alt_index_ * alt_period;
    const int64_t end = static_cast<int64_t>(o_.duration_s * 1e6);
    if (std::min(t_ins, t_alt) > end) return false;
    if (t_ins <= t_alt) {
      sample->kind = Sample::Kind::kIns;
      sample->t_us = t_ins;
      fill_ins(t_ins, &sample->ins);
      ++ins_index_;
    } else {
      sample->kind = Sample::Kind::kAltimeter;
      sample->t_us = t_alt;
      fill_altimeter(t_alt, &sample->altimeter);
      ++alt_index_;
    }
    return true;
  }

  std::string describe() const override {
    return "generated circle: " + std::to_string(o_.speed_mps) + " m/s, " + std::to_string(o_.height_agl_m) +
           " m AGL, radius " + std::to_string(o_.turn_radius_m) + " m";
  }

 private:
  struct State {
    double north, east, height, yaw, roll, pitch, vn, ve, vd;
  };
  State state(int64_t t_us) const {
    const double t = static_cast<double>(t_us) * 1e-6;
    const double omega = o_.speed_mps / o_.turn_radius_m;  // clockwise seen from above: yaw grows
    const double angle = omega * t;
    State s{};
    s.north = o_.turn_radius_m * std::sin(angle);
    s.east = o_.turn_radius_m * (1 - std::cos(angle));
    s.yaw = wrap_angle(angle);
    s.vn = o_.speed_mps * std::cos(angle);
    s.ve = o_.speed_mps * std::sin(angle);
    // A gentle climb/descent so pitch and altimeter range move.
    const double climb_amp = 10.0, climb_period = 120.0;
    const double w = 2 * M_PI / climb_period;
    s.height = o_.terrain_height_m + o_.height_agl_m + climb_amp * std::sin(w * t);
    s.vd = -climb_amp * w * std::cos(w * t);
    s.pitch = std::atan2(-s.vd, o_.speed_mps);
    s.roll = std::atan(o_.speed_mps * omega / 9.80665);  // coordinated turn, right wing down
    return s;
  }

  void fill_ins(int64_t t_us, ins_t* m) {
    const State s = state(t_us);
    *m = ins_t{};
    m->utime = t_us;
    m->roll = s.roll;
    m->pitch = s.pitch;
    m->yaw = s.yaw;
    m->velocity_ned[0] = s.vn;
    m->velocity_ned[1] = s.ve;
    m->velocity_ned[2] = s.vd;
    const GeodeticPoint geo = track_.geodetic(Eigen::Vector3d(s.north, s.east, 0.0));
    m->latitude_deg = geo.latitude_deg;
    m->longitude_deg = geo.longitude_deg;
    m->height_m = s.height;
    m->ins_status = 3;  // INS_SOLUTION_GOOD
    m->flags = ins_t::FLAG_ALIGNED | ins_t::FLAG_SOLUTION_GOOD | ins_t::FLAG_SIMULATED;
  }

  void fill_altimeter(int64_t t_us, altimeter_t* m) {
    const State s = state(t_us);
    *m = altimeter_t{};
    m->utime = t_us;
    for (int i = 0; i < 3; ++i) m->beam_body[i] = o_.beam_body[i];
    const Eigen::Vector3d beam_world =
        rotation_from_rpy(s.roll, s.pitch, s.yaw) * Eigen::Vector3d(o_.beam_body[0], o_.beam_body[1], o_.beam_body[2]);
    std::uniform_real_distribution<double> u(0, 1);
    std::normal_distribution<double> noise(0, 0.05);
    if (beam_world.z() <= 0.05 || u(rng_) < 0.01) {  // beam above the horizon, or a 1 % dropout
      m->validity = altimeter_t::VALID_NO_RETURN;
      m->signal_quality = 0;
      return;
    }
    m->range_m = (s.height - o_.terrain_height_m) / beam_world.z() + noise(rng_);
    m->signal_quality = static_cast<float>(0.6 + 0.3 * u(rng_));
    m->validity = altimeter_t::VALID_OK;
  }

  GeneratedFlightOptions o_;
  GeodeticTrack track_;  // the path on the ellipsoid from the start
  std::mt19937_64 rng_;
  int64_t ins_index_ = 0;
  int64_t alt_index_ = 0;
};

}  // namespace

std::unique_ptr<FlightSource> make_log_source(const std::string& path) { return std::make_unique<LogSource>(path); }

std::unique_ptr<FlightSource> make_generated_source(const GeneratedFlightOptions& options) {
  return std::make_unique<GeneratedSource>(options);
}

}  // namespace nadir::sim_serial
