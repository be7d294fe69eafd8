// nadir_fake_camera: an Aravis fake GigE Vision camera on a network
// interface (loopback inside a private network namespace) that serves a test
// pattern or the CAMERA_IMAGE frames of a (simulator) log, so the real
// nadir_camera_capture can be run and tested without a camera.

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <stdexcept>
#include <memory>
#include <thread>

#include "common/channels.h"
#include "common/shutdown.h"
#include "common/time_base.h"
#include "processes/camera_capture/fake_gige_camera.h"
#include "processes/camera_capture/frame_source.h"

int main(int argc, char** argv) {
  CLI::App app{
      "Hosts an Aravis fake GigE Vision camera (device id Aravis-Fake-<serial>) on a network interface, serving "
      "a test pattern or the CAMERA_IMAGE frames of an LCM log (e.g. the simulator's). Run it inside a private "
      "network namespace on lo; point nadir_camera_capture at it with --camera-id. Stops on SIGINT/SIGTERM.",
      "nadir_fake_camera"};
  nadir::FakeCameraOptions options;
  std::string log_path;
  std::string channel = nadir::channels::kCameraImage;
  size_t max_frames = 2000;
  app.add_option("--interface", options.interface_name, "network interface to listen on")->capture_default_str();
  app.add_option("--serial", options.serial, "serial number (device id Aravis-Fake-<serial>)")->capture_default_str();
  app.add_option("--log", log_path, "serve the CAMERA_IMAGE frames of this LCM log instead of the pattern");
  app.add_option("--channel", channel, "image channel in the log")->capture_default_str();
  app.add_option("--max-frames", max_frames, "frames to load from the log (memory bound)")->capture_default_str();
  bool paced = false;
  double start_delay_s = 0.0;
  int64_t log_origin_us = 0;
  int64_t vehicle_origin_us = 0;
  double speed = 1.0;
  app.add_flag("--paced", paced,
               "with --log: trigger each frame at its log time (start + (utime - first utime) / speed); run "
               "nadir_camera_capture with --trigger-mode software --software-rate-hz 0");
  app.add_option("--log-origin-us", log_origin_us, "paced: log utime played at --vehicle-origin-us");
  app.add_option("--vehicle-origin-us", vehicle_origin_us,
                 "paced: vehicle time (us) at which log utime --log-origin-us is played; lets several "
                 "players of one log (e.g. nadir_sim_serial) share one clock. Overrides --start-delay");
  app.add_option("--start-delay", start_delay_s, "paced: seconds from start to the first frame")
      ->check(CLI::Range(0.0, 3600.0));
  app.add_option("--speed", speed, "paced: log seconds per wall second")->check(CLI::Range(0.01, 100.0));
  app.add_option("--trigger-poll-hz", options.trigger_poll_hz, "how often software triggers are looked for")
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  try {
    std::shared_ptr<nadir::FrameSource> source;
    std::shared_ptr<nadir::LogFrameSource> log_source;
    if (log_path.empty()) {
      if (paced) throw std::runtime_error("--paced needs --log");
      source = std::make_shared<nadir::PatternFrameSource>();
    } else {
      log_source = std::make_shared<nadir::LogFrameSource>(log_path, channel, max_frames);
      source = log_source;
    }
    nadir::install_shutdown_handlers();
    nadir::FakeGigECamera camera(options, source);
    std::fprintf(stderr, "nadir_fake_camera: %s on %s serving %s\n", camera.device_id().c_str(),
                 options.interface_name.c_str(), source->describe().c_str());
    if (!paced) {
      while (!nadir::shutdown_requested()) std::this_thread::sleep_for(std::chrono::milliseconds(50));
    } else {
      // Trigger frame k at start + (utime_k - utime_0) / speed: the frames
      // reach the capture in step with the simulated trigger line, and a
      // pty feed of the same log (nadir_sim_serial) started with the same
      // delay stays aligned with them. Loops, keeping one period between laps.
      const size_t n = log_source->frames();
      const int64_t first = log_source->frame_utime(0);
      const int64_t period = n > 1 ? (log_source->frame_utime(n - 1) - first) / static_cast<int64_t>(n - 1) : 71429;
      const int64_t lap = log_source->frame_utime(n - 1) - first + period;
      int64_t start_mono = nadir::monotonic_now_us() + nadir::s_to_us(start_delay_s);
      int64_t start_vehicle = nadir::vehicle_time_now_us() + nadir::s_to_us(start_delay_s);
      if (vehicle_origin_us != 0) {
        start_vehicle = vehicle_origin_us + static_cast<int64_t>(static_cast<double>(first - log_origin_us) / speed);
        const int64_t ahead = start_vehicle - nadir::vehicle_time_now_us();
        if (ahead < 0) throw std::invalid_argument("--vehicle-origin-us puts the first frame in the past");
        start_mono = nadir::monotonic_now_us() + ahead;
      }
      std::fprintf(stderr, "nadir_fake_camera: paced: log utime %lld is vehicle time %lld (offset %lld us), speed %g\n",
                   static_cast<long long>(first), static_cast<long long>(start_vehicle),
                   static_cast<long long>(start_vehicle - first), speed);
      for (uint64_t k = 0; !nadir::shutdown_requested(); ++k) {
        const int64_t log_offset = static_cast<int64_t>(k / n) * lap + (log_source->frame_utime(k % n) - first);
        const int64_t due = start_mono + static_cast<int64_t>(static_cast<double>(log_offset) / speed);
        while (!nadir::shutdown_requested() && nadir::monotonic_now_us() < due) {
          std::this_thread::sleep_for(std::chrono::microseconds(std::min<int64_t>(20000, due - nadir::monotonic_now_us())));
        }
        if (nadir::shutdown_requested()) break;
        log_source->select(k % n);
        camera.trigger();
      }
    }
    std::fprintf(stderr, "nadir_fake_camera: stopped\n");
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "nadir_fake_camera: error: %s\n", e.what());
    return 2;
  }
}
