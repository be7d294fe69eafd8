// nadir_camera_capture: Aravis camera + trigger edges -> CAMERA_IMAGE,
// CAMERA_TRIGGER, STATUS (1 Hz) and CONFIG (at start and after every
// reconnect, with the camera's read-back settings).

#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <iostream>
#include <memory>

#include "common/channels.h"
#include "common/config.h"
#include "common/lcm_bus.h"
#include "common/paths.h"
#include "common/process_main.h"
#include "common/shutdown.h"
#include "common/status.h"
#include "common/time_base.h"
#include "processes/camera_capture/camera_capture.h"
#include "processes/camera_capture/gpiod_trigger_source.h"

namespace {

const char* kName = "camera_capture";

// The config as run, plus what the camera actually accepted.
nadir::Config with_effective(const nadir::Config& config, const nadir::EffectiveCameraSettings& settings) {
  YAML::Node root = YAML::Clone(config.node());
  root[kName]["effective"] = YAML::Load(settings.to_yaml());
  return nadir::Config(root, config.source(), "");
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Captures a GigE Vision / USB3 Vision camera through Aravis and publishes CAMERA_IMAGE with the trigger "
      "edge time (GPIO via libgpiod) or, without GPIO, the camera clock mapped to the vehicle time base; "
      "CAMERA_TRIGGER for every edge; STATUS at 1 Hz; CONFIG with the camera's read-back settings. Reconnects "
      "with backoff when the camera disappears.",
      "nadir_camera_capture"};
  std::string config_path;
  std::string lcm_url;
  std::string camera_id;
  std::string trigger_input;
  std::string trigger_mode;
  double software_rate_hz = -1.0;
  double status_period_s = 1.0;
  bool list_cameras = false;
  bool wait_for_camera = false;
  app.add_option("--config", config_path, "YAML config file (default: <checkout>/config/default.yaml)");
  app.add_option("--lcm-url", lcm_url, "LCM URL (default: $LCM_DEFAULT_URL or udpm with TTL 0)");
  app.add_option("--status-period", status_period_s, "seconds between STATUS messages")->check(CLI::Range(0.1, 60.0));
  app.add_option("--camera-id", camera_id, "overrides camera_capture.camera.id (Aravis id or serial)");
  app.add_option("--trigger-input", trigger_input, "overrides camera_capture.trigger_input.source (gpiod | none)");
  app.add_option("--trigger-mode", trigger_mode, "overrides camera_capture.camera.trigger.mode")
      ->check(CLI::IsMember({"free_run", "software", "hardware"}));
  app.add_option("--software-rate-hz", software_rate_hz,
                 "overrides camera_capture.camera.trigger.software_rate_hz (0: someone else fires the software "
                 "trigger, e.g. nadir_fake_camera --paced)")
      ->check(CLI::Range(0.0, 1000.0));
  app.add_flag("--wait-for-camera", wait_for_camera,
               "keep retrying when the camera is not there at start (camera_capture.reconnect.retry_at_start)");
  app.add_flag("--list-cameras", list_cameras, "print the cameras Aravis sees and exit");
  CLI11_PARSE(app, argc, argv);

  const std::string program = "nadir_camera_capture";
  if (list_cameras) {
    for (const std::string& d : nadir::AravisCamera::list_devices()) std::printf("%s\n", d.c_str());
    return 0;
  }
  try {
    if (config_path.empty()) config_path = nadir::default_config_path();
    nadir::Config config = nadir::Config::load_file(config_path);
    YAML::Node root = config.node();
    if (!camera_id.empty()) root[kName]["camera"]["id"] = camera_id;
    if (!trigger_input.empty()) root[kName]["trigger_input"]["source"] = trigger_input;
    if (!trigger_mode.empty()) root[kName]["camera"]["trigger"]["mode"] = trigger_mode;
    if (wait_for_camera) root[kName]["reconnect"]["retry_at_start"] = true;
    if (software_rate_hz >= 0) root[kName]["camera"]["trigger"]["software_rate_hz"] = software_rate_hz;
    const nadir::Config section = config.section_or_empty(kName);
    const nadir::CaptureOptions options = nadir::CaptureOptions::FromConfig(section);

    std::unique_ptr<nadir::TriggerSource> trigger;
    if (options.trigger_input == "gpiod") {
      trigger = std::make_unique<nadir::GpiodTriggerSource>(options.gpiod);
    } else if (options.trigger_input == "scripted") {
      throw nadir::ConfigError(config_path + ": key 'camera_capture.trigger_input.source' = scripted is for tests only");
    }
    const std::string trigger_text = trigger ? trigger->describe() : "none (camera clock timing)";

    nadir::LcmBusOptions bus_options;
    bus_options.url = lcm_url;
    nadir::LcmBus bus(bus_options);
    nadir::install_shutdown_handlers();
    std::fprintf(stderr, "%s: running on %s with %s, trigger input %s\n", program.c_str(), bus.url().c_str(),
                 config_path.c_str(), trigger_text.c_str());
    std::fprintf(stderr, "%s: options (%s):\n%s\n", program.c_str(), kName, section.dump().c_str());

    nadir::CameraCapture capture(options, bus, std::move(trigger));
    capture.set_on_connected([&](const nadir::EffectiveCameraSettings& settings) {
      std::fprintf(stderr, "%s: camera connected; effective settings:\n%s", program.c_str(), settings.to_yaml().c_str());
      for (const std::string& w : settings.warnings) std::fprintf(stderr, "%s: warning: %s\n", program.c_str(), w.c_str());
      nadir::publish_config(bus, kName, with_effective(config, settings), nadir::vehicle_time_now_us());
    });
    try {
      capture.connect();
    } catch (const nadir::CameraConfigError& e) {
      std::fprintf(stderr, "%s: error: %s\n", program.c_str(), e.what());
      return 2;
    } catch (const nadir::CameraUnavailable& e) {
      if (!options.retry_at_start) {
        std::fprintf(stderr, "%s: error: %s (set camera_capture.reconnect.retry_at_start: true to wait for it)\n",
                     program.c_str(), e.what());
        return 2;
      }
      std::fprintf(stderr, "%s: %s; retrying with backoff\n", program.c_str(), e.what());
      nadir::publish_config(bus, kName, config, nadir::vehicle_time_now_us());
    }

    const int64_t period_us = nadir::s_to_us(status_period_s);
    int64_t next_status_us = nadir::monotonic_now_us();
    bool was_connected = capture.connected();
    auto send_status = [&](int8_t forced_state) {
      nadir::StatusReport report = capture.status();
      if (forced_state >= 0) report.state = forced_state;
      const nadir::status_t msg = bus.status_message(kName, report);
      bus.publish(nadir::channels::kStatus, msg);
      return msg;
    };
    while (!nadir::shutdown_requested()) {
      capture.step(20);
      if (was_connected != capture.connected()) {
        const nadir::StatusReport r = capture.status();
        std::fprintf(stderr, "%s: %s\n", program.c_str(),
                     capture.connected() ? "camera reconnected" : ("camera lost: " + r.detail).c_str());
        was_connected = capture.connected();
      }
      const int64_t now = nadir::monotonic_now_us();
      if (now >= next_status_us) {
        send_status(-1);
        next_status_us = now + period_us;
      }
    }
    capture.stop();
    const nadir::status_t last = send_status(nadir::status_t::STATE_STOPPING);
    std::fprintf(stderr, "%s: stopped: %s\n", program.c_str(), nadir::format_status_line(last).c_str());
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: error: %s\n", program.c_str(), e.what());
    return 2;
  }
}
