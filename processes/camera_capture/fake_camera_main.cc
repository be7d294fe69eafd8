// nadir_fake_camera: an Aravis fake GigE Vision camera on a network
// interface (loopback inside a private network namespace) that serves a test
// pattern or the CAMERA_IMAGE frames of a (simulator) log, so the real
// nadir_camera_capture can be run and tested without a camera.

#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <memory>
#include <thread>

#include "common/channels.h"
#include "common/shutdown.h"
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
  app.add_option("--trigger-poll-hz", options.trigger_poll_hz, "how often software triggers are looked for")
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  try {
    std::shared_ptr<nadir::FrameSource> source;
    if (log_path.empty()) {
      source = std::make_shared<nadir::PatternFrameSource>();
    } else {
      source = std::make_shared<nadir::LogFrameSource>(log_path, channel, max_frames);
    }
    nadir::install_shutdown_handlers();
    nadir::FakeGigECamera camera(options, source);
    std::fprintf(stderr, "nadir_fake_camera: %s on %s serving %s\n", camera.device_id().c_str(),
                 options.interface_name.c_str(), source->describe().c_str());
    while (!nadir::shutdown_requested()) std::this_thread::sleep_for(std::chrono::milliseconds(50));
    std::fprintf(stderr, "nadir_fake_camera: stopped\n");
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "nadir_fake_camera: error: %s\n", e.what());
    return 2;
  }
}
