#pragma once
// An Aravis fake GigE Vision camera hosted in this process, serving images
// from a FrameSource. It answers discovery and GVCP on the given interface
// (loopback inside a private network namespace) and streams GVSP exactly like
// a real camera, so nadir_camera_capture talks real GigE Vision to it.

#include <memory>
#include <string>

#include "processes/camera_capture/frame_source.h"

typedef struct _ArvGvFakeCamera ArvGvFakeCamera;

namespace nadir {

struct FakeCameraOptions {
  std::string interface_name = "lo";
  std::string serial = "GV01";  // device id becomes "Aravis-Fake-<serial>"
  // How often the fake camera's loop looks for a software trigger. Aravis'
  // fake camera only checks between ticks, so this bounds trigger latency
  // (<= 5 ms at 200 Hz). Above ~500 Hz its loop polls with a zero timeout
  // and spins, starving the machine: measured trigger latency then grew to
  // hundreds of ms on a loaded 2-core host.
  double trigger_poll_hz = 200.0;
};

class FakeGigECamera {
 public:
  // Throws std::runtime_error when the camera cannot listen on the interface.
  FakeGigECamera(const FakeCameraOptions& options, std::shared_ptr<FrameSource> source);
  ~FakeGigECamera();
  FakeGigECamera(const FakeGigECamera&) = delete;
  FakeGigECamera& operator=(const FakeGigECamera&) = delete;

  std::string device_id() const { return "Aravis-Fake-" + options_.serial; }
  // Fires the camera's FrameStart software trigger from this side, as the
  // trigger line would (the capture sets TriggerSource=Software and leaves
  // firing to us). Served on the camera's next poll tick.
  void trigger();

 public:
  struct FillContext;  // what the fill callback needs: camera registers and the source

 private:
  FakeCameraOptions options_;
  std::unique_ptr<FillContext> context_;
  std::shared_ptr<FrameSource> source_;
  ArvGvFakeCamera* camera_ = nullptr;
};

}  // namespace nadir
