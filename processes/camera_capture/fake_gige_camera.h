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
  // fake camera only checks between ticks, so this bounds trigger latency.
  double trigger_poll_hz = 1000.0;
};

class FakeGigECamera {
 public:
  // Throws std::runtime_error when the camera cannot listen on the interface.
  FakeGigECamera(const FakeCameraOptions& options, std::shared_ptr<FrameSource> source);
  ~FakeGigECamera();
  FakeGigECamera(const FakeGigECamera&) = delete;
  FakeGigECamera& operator=(const FakeGigECamera&) = delete;

  std::string device_id() const { return "Aravis-Fake-" + options_.serial; }

 private:
  FakeCameraOptions options_;
  std::shared_ptr<FrameSource> source_;
  ArvGvFakeCamera* camera_ = nullptr;
};

}  // namespace nadir
