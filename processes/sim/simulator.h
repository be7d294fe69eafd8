#pragma once
// The whole simulated vehicle: trajectory, terrain, camera + trigger, INS,
// altimeter and ground truth, producing encoded messages in nondecreasing
// sensor-time order (deterministic order for equal times). Main writes them
// to a log or publishes them live; tests read them directly.

#include <cstdint>
#include <memory>
#include <queue>
#include <string>
#include <vector>

#include "common/geodetic.h"
#include "processes/sim/flight_profile.h"
#include "processes/sim/gauss_markov.h"
#include "processes/sim/renderer.h"
#include "processes/sim/sensor_options.h"
#include "processes/sim/sensor_outage.h"
#include "processes/sim/sim_camera.h"
#include "processes/sim/sim_random.h"
#include "processes/sim/terrain.h"

namespace nadir::sim {

// The camera as it really is: `configured` with the sensor set's installation
// and intrinsic errors applied (each only when set). What the simulator
// renders through; tools that compare against the simulator's truth
// (nadir_track_truth) use it too.
SimCamera true_camera(const SimCamera& configured, const CameraSensorOptions& errors);

// 2026-01-01T00:00:00Z in microseconds: the fixed epoch of log mode, so the
// same profile and seed give a byte-identical log.
constexpr int64_t kLogEpochUs = 1767225600LL * 1000000LL;

struct SimEvent {
  int64_t utime = 0;
  std::string channel;
  std::vector<uint8_t> data;
};

struct SimulatorOptions {
  uint64_t seed = 1;
  int64_t epoch_us = kLogEpochUs;  // vehicle time of t = 0
  double duration_s = -1.0;        // <= 0: the whole profile
  std::string camera_yaml;         // the camera section used, for CONFIG
  // false: no CAMERA_IMAGE messages at all (triggers, INS, altimeter and
  // truth unchanged) -- for sensor statistics over long flights in tests.
  bool render_images = true;
  std::vector<SensorOutage> outages;  // faults cut into the flight (none by default)
};

struct SimulatorCounts {
  int64_t frames = 0;          // triggers
  int64_t images = 0;          // images published
  int64_t dropped_frames = 0;
  int64_t ins = 0;
  int64_t altimeter = 0;
  int64_t altimeter_dropouts = 0;
  int64_t outage_messages = 0;  // messages withheld or degraded by outages
  int64_t ground_truth = 0;
  int64_t marched_pixels = 0;
};

class Simulator {
 public:
  Simulator(const FlightProfile& profile, const SimCamera& camera, const SensorOptions& sensors,
            const SimulatorOptions& options);

  // Renders the first view once so the texture tiles in sight exist before a
  // live clock starts (no effect on any message).
  void warm_up();
  // Moves t = 0 to a new vehicle time; only before the first next().
  void set_epoch(int64_t epoch_us);

  // Next message; false when the run is over. The first message is CONFIG.
  bool next(SimEvent* event);

  double duration_s() const { return duration_s_; }
  double sim_time_s() const { return sim_time_s_; }
  const SimulatorCounts& counts() const { return counts_; }
  const Trajectory& trajectory() const { return trajectory_; }
  const Terrain& terrain() const { return terrain_; }
  Renderer& renderer() { return renderer_; }
  // The true camera the renderer uses (the configured one with the sensor
  // set's boresight, focal and distortion errors applied).
  const SimCamera& camera() const { return camera_; }
  // The camera as configured (what the estimator believes).
  const SimCamera& configured_camera() const { return configured_camera_; }
  // The YAML published in CONFIG: profile + sensor set + seed + camera.
  const std::string& config_yaml() const { return config_yaml_; }

  // Truth ray cast along the altimeter's true beam (the configured optical
  // axis, misaligned as the sensor set says) from its true origin at time t (s).
  bool altimeter_truth_range(double t, double* range_m) const;

 private:
  enum Kind : int { kConfig = 0, kTrigger, kImage, kFrameTruth, kIns, kInsTruth, kAltimeter };
  struct Pending {
    int64_t utime;
    int kind;
    int64_t index;
    bool operator>(const Pending& o) const {
      if (utime != o.utime) return utime > o.utime;
      if (kind != o.kind) return kind > o.kind;
      return index > o.index;
    }
  };
  struct FrameDraw {
    int64_t true_us = 0, reported_us = 0;
    bool dropped = false;
  };

  void schedule_frame(int64_t k);
  void schedule_ins(int64_t k);
  void schedule_altimeter(int64_t k);
  void make_trigger(int64_t k, SimEvent* e);
  void make_image(int64_t k, SimEvent* e);
  void make_truth(int64_t t_us, int8_t kind, SimEvent* e);
  void make_ins(int64_t k, SimEvent* e);
  void make_altimeter(int64_t k, SimEvent* e);
  void make_config(SimEvent* e);
  // Makes the message of `p`; false when an outage withholds it.
  bool make(const Pending& p, SimEvent* e);
  const SensorOutage* outage(SensorOutage::Kind kind, int64_t t_us) const {
    return find_outage(options_.outages, kind, static_cast<double>(t_us) * 1e-6);
  }

  FlightProfile profile_;
  SimCamera configured_camera_;
  SensorOptions sensors_;
  SimCamera camera_;  // true camera
  SimulatorOptions options_;
  Terrain terrain_;
  Trajectory trajectory_;
  Renderer renderer_;
  GeodeticTrack ins_track_;  // INS latitude/longitude: the path from the profile's reference point
  double duration_s_ = 0.0;
  int64_t duration_us_ = 0;
  double sim_time_s_ = 0.0;
  bool started_ = false;
  std::string config_yaml_;
  std::priority_queue<Pending, std::vector<Pending>, std::greater<Pending>> queue_;
  RandomStream trigger_rng_, ins_rng_, altimeter_rng_;
  RandomStream ins_gm_rng_;      // correlated roll/pitch errors only
  RandomStream ins_yaw_gm_rng_;  // correlated yaw error only
  GaussMarkov roll_gm_, pitch_gm_, yaw_gm_;
  Eigen::Vector3d altimeter_beam_body_ = Eigen::Vector3d::UnitZ();  // true beam
  std::vector<FrameDraw> frames_;  // by frame index (small: 14 Hz)
  double yaw_bias_rad_ = 0.0;
  int64_t last_ins_k_ = -1;
  std::vector<uint8_t> image_buffer_;
  SimulatorCounts counts_;
};

}  // namespace nadir::sim
