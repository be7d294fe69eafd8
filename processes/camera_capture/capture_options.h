#pragma once
// Everything nadir_camera_capture reads from its config section
// (camera_capture:), with the allowed ranges checked at start.

#include <string>

#include "common/clock_sync.h"
#include "common/config.h"
#include "processes/camera_capture/camera_options.h"
#include "processes/camera_capture/frame_association.h"
#include "processes/camera_capture/gpiod_trigger_source.h"
#include "processes/camera_capture/image_time.h"

namespace nadir {

struct CaptureOptions {
  CameraOptions camera;
  // Trigger edges: "gpiod" (GPIO line), "none" (time frames by the camera
  // clock), "scripted" (only valid when a test supplies the source).
  std::string trigger_input = "none";
  GpiodTriggerOptions gpiod;
  ImageTimingOptions timing;
  AssociationOptions association;
  ClockSyncOptions clock_sync;
  // Frames without a trigger edge: publish flagged (trigger_sequence -1 and a
  // lower time_quality) or drop them.
  bool publish_unassociated = true;
  // Reconnect with backoff when the camera stops answering or frames stop.
  double reconnect_initial_backoff_s = 0.5;
  double reconnect_max_backoff_s = 8.0;
  double frame_timeout_s = 2.0;    // no frame this long while one is expected: reconnect
  bool retry_at_start = false;     // keep retrying when no camera is there at start

  static CaptureOptions FromConfig(const Config& section);
  void Check() const;
};

}  // namespace nadir
