// nadir_sim: the simulated vehicle. Writes an LCM log (fixed epoch, byte-
// identical for the same profile and seed) or publishes live in scaled real
// time, on exactly the channels of the real camera and INS/altimeter drivers
// plus GROUND_TRUTH.

#include <pthread.h>
#include <sched.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <memory>
#include <optional>
#include <thread>
#include <vector>

#include "common/channels.h"
#include "common/config.h"
#include "common/json_writer.h"
#include "common/lcm_bus.h"
#include "common/log_file.h"
#include "common/paths.h"
#include "common/progress.h"
#include "common/shutdown.h"
#include "common/status.h"
#include "common/time_base.h"
#include "processes/sim/render_ahead.h"
#include "processes/sim/sim_rotation.h"
#include "processes/sim/simulator.h"
#ifdef NADIR_HAVE_RASTER_WORLD
#include "tools/map/raster_ground.h"
#endif

namespace {

// A profile naming a real place (world: orthophoto + DEM) flies over it;
// a world that cannot be used is a configuration error, as a bad profile is.
void attach_world(nadir::sim::FlightProfile* profile, uint64_t seed) {
  if (!profile->has_world()) return;
#ifdef NADIR_HAVE_RASTER_WORLD
  try {
    nadir::map::attach_raster_world(profile, seed);
  } catch (const nadir::map::MapError& e) {
    throw nadir::ConfigError(profile->source + ": world: " + e.what());
  }
#else
  (void)seed;
  throw nadir::ConfigError(profile->source + ": world: this nadir_sim was built without GDAL (libgdal-dev, "
                           "launch_scripts/setup.sh), which reads the orthophoto and DEM");
#endif
}

struct Arguments {
  std::string profile;
  uint64_t seed = 1;
  double duration_s = -1.0;
  std::string out;
  bool live = false;
  int render_nice = 10;
  int publish_rt_priority = 0;
  double rate = 1.0;
  std::string lcm_url;
  std::string config_path;
  std::string config_overlay;
  std::string sensors_path;
  std::string sensor_set = "standard";
  std::optional<double> relief_scale;
  std::optional<double> altitude_agl_m;
  std::optional<double> roll_pitch_noise_deg, yaw_noise_deg, altimeter_noise_pct;
  std::vector<std::string> outages;
  bool json = false;
  double snapshot_s = -1.0;
  std::string png;
  double png_scale = 1.0;
};

void print_summary(const Arguments& args, const nadir::sim::Simulator& sim, double wall_s) {
  const auto& c = sim.counts();
  const double fps = wall_s > 0 ? c.images / wall_s : 0.0;
  if (args.json) {
    nadir::JsonWriter j;
    j.begin_object()
        .field("profile", args.profile)
        .field("seed", static_cast<int64_t>(args.seed))
        .field("out", args.live ? std::string("live") : args.out)
        .field("sim_seconds", sim.sim_time_s())
        .field("wall_seconds", wall_s)
        .field("realtime_factor", wall_s > 0 ? sim.sim_time_s() / wall_s : 0.0)
        .field("rendered_frames_per_s", fps)
        .field("triggers", c.frames)
        .field("images", c.images)
        .field("dropped_frames", c.dropped_frames)
        .field("ins", c.ins)
        .field("altimeter", c.altimeter)
        .field("altimeter_dropouts", c.altimeter_dropouts)
        .field("ground_truth", c.ground_truth)
        .field("occlusion_marched_pixels", c.marched_pixels)
        .end_object();
    std::printf("%s\n", j.str().c_str());
  }
  std::fprintf(stderr,
               "nadir_sim: %.1f s simulated in %.1f s (%.2fx real time, %.1f rendered frames/s): %lld images "
               "(%lld dropped), %lld INS, %lld altimeter (%lld dropouts), %lld ground truth\n",
               sim.sim_time_s(), wall_s, wall_s > 0 ? sim.sim_time_s() / wall_s : 0.0, fps,
               static_cast<long long>(c.images), static_cast<long long>(c.dropped_frames),
               static_cast<long long>(c.ins), static_cast<long long>(c.altimeter),
               static_cast<long long>(c.altimeter_dropouts), static_cast<long long>(c.ground_truth));
}

int run_log(const Arguments& args, nadir::sim::Simulator& sim) {
  nadir::LogWriter writer(args.out);
  nadir::ProgressBar progress("sim " + args.profile, sim.duration_s(), nadir::stderr_is_terminal());
  nadir::sim::SimEvent event;
  const auto start = std::chrono::steady_clock::now();
  nadir::install_shutdown_handlers();
  while (!nadir::shutdown_requested() && sim.next(&event)) {
    writer.write(event.utime, event.channel, event.data.data(), event.data.size());
    progress.update(sim.sim_time_s());
  }
  writer.flush();
  progress.finish();
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  print_summary(args, sim, wall);
  if (nadir::shutdown_requested()) {
    std::fprintf(stderr, "nadir_sim: interrupted; %s holds the first %.1f s\n", args.out.c_str(), sim.sim_time_s());
    return 130;
  }
  std::fprintf(stderr, "nadir_sim: wrote %lld events to %s\n", static_cast<long long>(writer.events()),
               args.out.c_str());
  return 0;
}

// One frame as the camera sees it (noise included), for documentation.
int run_snapshot(const Arguments& args, nadir::sim::Simulator& sim) {
  if (args.png.empty()) throw std::runtime_error("--snapshot needs --png FILE");
  const double t = std::min(args.snapshot_s, sim.duration_s());
  const nadir::sim::TruthState s = sim.trajectory().at(t);
  std::vector<uint8_t> image;
  sim.renderer().render(s.position_ned, s.world_from_body() * sim.camera().body_from_camera, args.seed, &image);
  cv::Mat view(sim.camera().height, sim.camera().width, CV_8UC1, image.data());
  if (args.png_scale < 1.0) {
    cv::Mat small;
    cv::resize(view, small, cv::Size(), args.png_scale, args.png_scale, cv::INTER_AREA);
    view = small;
  }
  if (!cv::imwrite(args.png, view)) throw std::runtime_error(args.png + ": cannot write PNG");
  const double terrain = sim.terrain().height(s.position_ned.x(), s.position_ned.y());
  std::fprintf(stderr, "nadir_sim: t = %.2f s, %.1f m above ground, roll %.2f pitch %.2f yaw %.2f deg -> %s\n", t,
               -s.position_ned.z() - terrain, nadir::sim::rad2deg(s.roll), nadir::sim::rad2deg(s.pitch),
               nadir::sim::rad2deg(s.yaw), args.png.c_str());
  return 0;
}

// `epoch_us` (vehicle time of t = 0) and `start_mono` (the monotonic clock at
// t = 0) were taken together: message due times come from them, not from
// when this function got going.
int run_live(const Arguments& args, nadir::sim::Simulator& sim, int64_t epoch_us, int64_t start_mono) {
  nadir::LcmBusOptions bus_options;
  bus_options.url = args.lcm_url;
  nadir::LcmBus bus(bus_options);
  nadir::install_shutdown_handlers();
  std::fprintf(stderr, "nadir_sim: live on %s at %.2fx real time\n", bus.url().c_str(), args.rate);
  // Render ahead so each message leaves at its due time (a real camera does
  // not take a render time to deliver a frame).
  nadir::sim::RenderAhead ahead(sim, 256, args.render_nice);
  // After the render thread has started, so that it keeps the ordinary
  // scheduling it was created with: only the publisher runs in real time.
  if (args.publish_rt_priority > 0) {
    sched_param param{};
    param.sched_priority = args.publish_rt_priority;
    const int err = pthread_setschedparam(pthread_self(), SCHED_FIFO, &param);
    if (err != 0) {
      throw std::runtime_error("--publish-rt-priority " + std::to_string(args.publish_rt_priority) +
                               ": SCHED_FIFO not permitted (" + std::strerror(err) +
                               "; needs root or CAP_SYS_NICE)");
    }
    std::fprintf(stderr, "nadir_sim: publisher under SCHED_FIFO %d, renderer at niceness %d\n",
                 args.publish_rt_priority, args.render_nice);
  }
  int64_t next_status = nadir::monotonic_now_us();
  int64_t published = 0;
  auto send_status = [&](int8_t state) {
    nadir::StatusReport report;
    report.state = state;
    report.published = published;
    const nadir::sim::SimulatorCounts counts = ahead.counts();
    report.dropped = counts.dropped_frames;
    report.counters = {{"sim_time_s", ahead.sim_time_s()},
                       {"images", static_cast<double>(counts.images)},
                       {"ins", static_cast<double>(counts.ins)},
                       {"altimeter", static_cast<double>(counts.altimeter)},
                       {"rate", args.rate}};
    bus.publish(nadir::channels::kStatus, bus.status_message("sim", report));
  };
  nadir::sim::SimEvent event;
  while (!nadir::shutdown_requested() && ahead.pop(&event)) {
    const int64_t due = start_mono + static_cast<int64_t>((event.utime - epoch_us) / args.rate);
    for (;;) {
      const int64_t now = nadir::monotonic_now_us();
      if (now >= next_status) {
        send_status(nadir::status_t::STATE_OK);
        next_status = std::max(next_status + 1000000, now + 1);  // never a burst after a stall
      }
      if (now >= due || nadir::shutdown_requested()) break;
      std::this_thread::sleep_for(std::chrono::microseconds(std::min<int64_t>(due - now, next_status - now)));
    }
    bus.publish_raw(event.channel, event.data.data(), event.data.size());
    ++published;
    bus.handle(0);
  }
  send_status(nadir::status_t::STATE_STOPPING);
  ahead.stop();
  print_summary(args, sim, (nadir::monotonic_now_us() - start_mono) * 1e-6);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Arguments args;
  CLI::App app{
      "Flight simulator: procedural terrain rendered by the downward camera, INS, laser altimeter and trigger "
      "models, and ground truth. Writes an LCM log (--out) or publishes live (--live) on CAMERA_IMAGE, "
      "CAMERA_TRIGGER, INS, ALTIMETER, GROUND_TRUTH, CONFIG (and STATUS when live).",
      "nadir_sim"};
  app.add_option("--profile", args.profile, "flight profile: NAME (config/profiles/NAME.yaml) or a YAML file")
      ->required();
  app.add_option("--seed", args.seed, "random seed (terrain, motion oscillations, sensor noise)");
  app.add_option("--duration", args.duration_s, "seconds to simulate (default: the whole profile)")
      ->check(CLI::PositiveNumber);
  auto* out = app.add_option("--out", args.out, "LCM log file to write");
  auto* live = app.add_flag("--live", args.live, "publish live in (scaled) real time instead of writing a log");
  out->excludes(live);
  auto* render_nice = app.add_option("--render-nice", args.render_nice,
                 "live mode: niceness of the render-ahead thread, so rendering never delays the estimators "
                 "on a shared machine (default 10; 0 = same priority)")
      ->check(CLI::Range(0, 19));
  auto* publish_rt = app.add_option("--publish-rt-priority", args.publish_rt_priority,
                 "live mode: run the publisher thread (the stand-in for the camera and INS drivers) under "
                 "SCHED_FIFO at this priority, the renderer staying at its niceness (1-98; needs root or "
                 "CAP_SYS_NICE; default 0 = ordinary scheduling)")
      ->check(CLI::Range(0, 98));
  render_nice->needs(live);
  publish_rt->needs(live);
  app.add_option("--rate", args.rate, "live mode: simulated seconds per wall second")->check(CLI::Range(0.01, 100.0));
  app.add_option("--lcm-url", args.lcm_url, "live mode: LCM URL (default: $LCM_DEFAULT_URL or udpm with TTL 0)");
  app.add_option("--config", args.config_path, "config with the camera: section (default: config/default.yaml)");
  app.add_option("--config-overlay", args.config_overlay,
                 "YAML fragment merged into that config key by key, e.g. config/sim_camera_12mp.yaml "
                 "(a 12 MP camera)");
  app.add_option("--sensors", args.sensors_path, "sensor model file (default: config/sim_sensors.yaml)");
  app.add_option("--sensor-set", args.sensor_set, "sensor set in that file (default: standard)");
  app.add_option("--relief-scale", args.relief_scale,
                 "override the profile's terrain.relief_scale (0 = flat ground .. 3); the same flight and seed "
                 "over other relief. Recorded in CONFIG (profile.terrain, profile_overrides)");
  app.add_option("--altitude-agl-m", args.altitude_agl_m,
                 "override the profile's altitude_agl_m (30..3000): the same flight shifted up or down, e.g. flat "
                 "ground flown at a relief flight's height above its ground. Recorded in CONFIG (profile, "
                 "profile_overrides)");
  app.add_option("--roll-pitch-noise-deg", args.roll_pitch_noise_deg, "override INS roll/pitch white noise sigma");
  app.add_option("--yaw-noise-deg", args.yaw_noise_deg, "override INS yaw white noise sigma");
  app.add_option("--altimeter-noise-pct", args.altimeter_noise_pct, "override altimeter noise, percent of range");
  app.add_option("--outage", args.outages,
                 "cut a sensor outage into the flight (repeatable): KIND:START_S:DURATION_S[:CONTRAST], KIND one of "
                 "altimeter (no return), ins, camera (not published), texture (contrast cut to CONTRAST, default 0.03)");
  app.add_option("--snapshot", args.snapshot_s, "render only the frame at this flight time (s) into --png and exit")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--png", args.png, "PNG file for --snapshot");
  app.add_option("--png-scale", args.png_scale, "scale the --snapshot PNG (area averaging), e.g. 0.5")
      ->check(CLI::Range(0.05, 1.0));
  app.add_flag("--json", args.json, "print a machine-readable summary on stdout at the end");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  if (args.snapshot_s < 0 && !args.live && args.out.empty()) {
    std::fprintf(stderr, "nadir_sim: give --out FILE.lcmlog or --live\n");
    return 2;
  }
  try {
    const std::string config_path = args.config_path.empty() ? nadir::default_config_path() : args.config_path;
    nadir::Config config = nadir::Config::load_file(config_path);
    if (!args.config_overlay.empty()) config.apply_overlay(nadir::Config::load_file(args.config_overlay));
    const nadir::sim::SimCamera camera = nadir::sim::SimCamera::from_config(config);
    const std::string sensors_path =
        args.sensors_path.empty() ? nadir::checkout_root() + "/config/sim_sensors.yaml" : args.sensors_path;
    nadir::sim::SensorOptions sensors =
        nadir::sim::SensorOptions::from_config(nadir::Config::load_file(sensors_path), args.sensor_set);
    if (args.roll_pitch_noise_deg) sensors.ins.roll_pitch_noise_deg = *args.roll_pitch_noise_deg;
    if (args.yaw_noise_deg) sensors.ins.yaw_noise_deg = *args.yaw_noise_deg;
    if (args.altimeter_noise_pct) sensors.altimeter.noise_pct = *args.altimeter_noise_pct;
    if (args.roll_pitch_noise_deg || args.yaw_noise_deg || args.altimeter_noise_pct) sensors.source = "command line";
    sensors.Check();
    nadir::sim::FlightProfile profile =
        nadir::sim::FlightProfile::load(nadir::sim::FlightProfile::resolve(args.profile));
    // CONFIG names the profile relative to the checkout, so the same profile
    // and seed give the same log bytes in any checkout.
    const std::string root = nadir::checkout_root() + "/";
    if (profile.source.compare(0, root.size(), root) == 0) profile.source = profile.source.substr(root.size());
    if (args.relief_scale) profile.override_relief_scale(*args.relief_scale);
    if (args.altitude_agl_m) profile.override_altitude_agl(*args.altitude_agl_m);
    attach_world(&profile, args.seed);

    nadir::sim::SimulatorOptions options;
    options.seed = args.seed;
    options.duration_s = args.duration_s;
    options.camera_yaml = config.section("camera").dump();
    for (const std::string& o : args.outages) options.outages.push_back(nadir::sim::SensorOutage::parse(o));
    options.epoch_us = args.live ? nadir::vehicle_time_now_us() : nadir::sim::kLogEpochUs;
    nadir::sim::Simulator sim(profile, camera, sensors, options);
    std::fprintf(stderr, "nadir_sim: profile %s (%s), %.1f s, seed %llu, sensors %s:%s\n", profile.name.c_str(),
                 profile.source.c_str(), sim.duration_s(), static_cast<unsigned long long>(args.seed),
                 sensors_path.c_str(), args.sensor_set.c_str());
    if (args.snapshot_s >= 0) return run_snapshot(args, sim);
    if (args.live) {
      sim.warm_up();  // the first view's texture, before the live clock starts
      // t = 0 lies a little ahead, so that the bus and the render-ahead
      // thread are up and the first frame is rendered when the first message
      // is due. Taken when the clock started after that set-up instead, the
      // epoch made every message leave ~1.3 ms after its sensor time.
      const int64_t lead_us = 200000;
      const int64_t epoch = nadir::vehicle_time_now_us() + lead_us;
      const int64_t start_mono = nadir::monotonic_now_us() + lead_us;
      sim.set_epoch(epoch);
      return run_live(args, sim, epoch, start_mono);
    }
    return run_log(args, sim);
  } catch (const nadir::ConfigError& e) {
    // A bad profile, sensor set or camera config: nothing was simulated.
    std::fprintf(stderr, "nadir_sim: error: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "nadir_sim: %s\n", e.what());
    return 1;
  }
}
