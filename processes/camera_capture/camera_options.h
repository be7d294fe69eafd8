#pragma once
// How the camera is set up (config section camera_capture.camera). Every
// field is written to the camera and read back: cameras round and clamp, and
// the read-back values are what get printed and published in CONFIG.

#include <string>
#include <vector>

#include "common/config.h"

namespace nadir {

struct CameraOptions {
  std::string id;                  // Aravis device id or serial number; empty: first camera found
  std::string pixel_format = "Mono8";  // Mono8; Mono10/12/16 (16-bit words); Bayer*8 (converted to mono)
  int roi_x = 0, roi_y = 0;
  int roi_width = 0, roi_height = 0;   // 0: the camera's current/maximum
  int binning_x = 1, binning_y = 1;
  std::string exposure_mode = "fixed"; // fixed | auto
  double exposure_us = 2000.0;         // fixed exposure
  double exposure_auto_min_us = 100.0; // limits for auto exposure
  double exposure_auto_max_us = 8000.0;
  double gain_db = 0.0;
  double frame_rate_hz = 14.0;         // free-run rate; software trigger rate
  std::string trigger_mode = "hardware";   // free_run | software | hardware
  std::string trigger_line = "Line0";      // hardware trigger input on the camera
  std::string trigger_activation = "RisingEdge";
  double trigger_debounce_us = 0.0;        // 0: leave the camera's setting alone
  double software_trigger_rate_hz = 14.0;  // software mode: 0 = triggered by the caller
  int packet_size = 0;                     // GigE: 0 = negotiate the largest that works
  int packet_delay_ns = 0;                 // GigE inter-packet delay
  int stream_buffers = 16;
  // Features that only warn when the camera lacks them.
  std::vector<std::string> optional_features = {"BinningHorizontal", "BinningVertical", "LineDebouncerTime",
                                                "TriggerActivation", "AcquisitionFrameRate"};

  static CameraOptions FromConfig(const Config& section);
  void Check() const;
  bool is_optional(const std::string& feature) const;
};

}  // namespace nadir
