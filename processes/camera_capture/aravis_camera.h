#pragma once
// One Aravis camera: find it by id or serial, configure it with read-back,
// stream into a pool of buffers, report stream statistics and loss of
// control. Owns the ArvCamera/ArvStream; destroying it stops acquisition and
// releases the camera (GigE control channel) cleanly.

#include <atomic>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "processes/camera_capture/camera_options.h"

typedef struct _ArvCamera ArvCamera;
typedef struct _ArvStream ArvStream;
typedef struct _ArvBuffer ArvBuffer;

namespace nadir {

// The camera is absent or stopped answering: worth retrying.
class CameraUnavailable : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The camera cannot do what config asks (feature, pixel format): retrying
// will not help; the message names the feature and the config key.
class CameraConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// What the camera actually runs with, read back after writing.
struct EffectiveCameraSettings {
  std::string device_id;
  std::string serial;
  std::string vendor;
  std::string model;
  std::string pixel_format;
  int x = 0, y = 0, width = 0, height = 0;
  int binning_x = 1, binning_y = 1;
  std::string exposure_mode;
  double exposure_us = 0.0;
  double gain_db = 0.0;
  double frame_rate_hz = 0.0;
  std::string trigger_mode;
  std::string trigger_source;
  double packet_size = 0.0;
  double packet_delay_ns = 0.0;
  int payload_bytes = 0;
  std::vector<std::string> warnings;  // optional features that were missing
  std::string to_yaml() const;        // a YAML map of the values above
};

struct StreamStatistics {
  uint64_t completed = 0;
  uint64_t failures = 0;
  uint64_t underruns = 0;
};

class AravisCamera {
 public:
  // Finds the camera (options.id: Aravis id or serial; empty: first) and
  // configures it. Throws CameraUnavailable or CameraConfigError.
  explicit AravisCamera(const CameraOptions& options);
  ~AravisCamera();
  AravisCamera(const AravisCamera&) = delete;
  AravisCamera& operator=(const AravisCamera&) = delete;

  const EffectiveCameraSettings& settings() const { return settings_; }

  void start();  // creates the stream, queues the buffers, starts acquisition
  // Next buffer (any status) or nullptr after timeout_us. The caller gives it
  // back with requeue().
  ArvBuffer* pop(uint64_t timeout_us);
  void requeue(ArvBuffer* buffer);
  void software_trigger();  // throws CameraUnavailable
  StreamStatistics statistics() const;
  // Set from Aravis' heartbeat thread when the camera stops answering or
  // another host took control.
  bool control_lost() const { return control_lost_->load(); }

  // Device ids currently visible to Aravis ("id (serial)").
  static std::vector<std::string> list_devices();

 private:
  void configure();
  void close();

  CameraOptions options_;
  ArvCamera* camera_ = nullptr;
  ArvStream* stream_ = nullptr;
  unsigned long control_lost_handler_ = 0;
  std::shared_ptr<std::atomic<bool>> control_lost_ = std::make_shared<std::atomic<bool>>(false);
  EffectiveCameraSettings settings_;
  bool acquiring_ = false;
};

}  // namespace nadir
