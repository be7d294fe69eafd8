#pragma once
// The capture loop: Aravis frames + trigger edges -> association -> image
// time -> CAMERA_IMAGE, and CAMERA_TRIGGER for every edge. Reconnects with
// backoff when the camera disappears, without restarting the process.
//
// Single-threaded by design: step() polls the trigger source, pops Aravis
// buffers (Aravis receives packets on its own stream thread) and publishes.
// Edge times come from the kernel (GPIO) and buffer times from the camera or
// the Aravis receive thread, so how promptly step() runs never changes a
// timestamp; it only adds publish latency, which STATUS reports.

#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>

#include "common/bus.h"
#include "common/clock_sync.h"
#include "common/status.h"
#include "processes/camera_capture/aravis_camera.h"
#include "processes/camera_capture/capture_options.h"
#include "processes/camera_capture/frame_association.h"
#include "processes/camera_capture/image_message.h"
#include "processes/camera_capture/trigger_source.h"

namespace nadir {

class CameraCapture {
 public:
  // `trigger` may be null: frames are then timed by the camera clock.
  CameraCapture(const CaptureOptions& options, Bus& bus, std::unique_ptr<TriggerSource> trigger);
  ~CameraCapture();

  // Opens and starts the camera now. Throws CameraUnavailable (absent) or
  // CameraConfigError (cannot do what config asks). After a failure step()
  // keeps retrying with backoff.
  void connect();
  // One pass of the loop; blocks at most max_wait_ms.
  void step(int max_wait_ms);
  // Stops acquisition and releases the camera (also done by the destructor).
  void stop();

  // Software trigger mode: asks step() to fire one trigger (thread-safe).
  void request_software_trigger() { software_requests_.fetch_add(1); }
  // Called (vehicle time) right before each software trigger is sent: a test
  // or a HIL harness emits the matching edge on its trigger source here.
  void set_software_trigger_hook(std::function<void(int64_t vehicle_us)> hook) { trigger_hook_ = std::move(hook); }
  // Called after every successful (re)connect with the read-back settings.
  void set_on_connected(std::function<void(const EffectiveCameraSettings&)> hook) { on_connected_ = std::move(hook); }

  bool connected() const { return camera_ != nullptr; }
  const EffectiveCameraSettings& settings() const { return settings_; }
  StatusReport status() const;
  const AssociationCounters& association_counters() const { return associator_.counters(); }
  int64_t published_images() const { return published_images_; }
  int64_t reconnects() const { return reconnects_; }

 private:
  struct HeldFrame {
    ArvBuffer* buffer = nullptr;
  };
  void disconnect(const std::string& why);
  void try_reconnect(int64_t now_mono_us);
  void handle_edges(const std::vector<TriggerEdge>& edges);
  void handle_buffer(ArvBuffer* buffer);
  void publish_decisions(std::vector<AssociationDecision> decisions);
  void publish_image(ArvBuffer* buffer, int64_t utime, int64_t trigger_utime, int64_t trigger_sequence,
                     int8_t time_quality);
  void release(ArvBuffer* buffer);

  CaptureOptions options_;
  Bus& bus_;
  std::unique_ptr<TriggerSource> trigger_;
  std::unique_ptr<AravisCamera> camera_;
  EffectiveCameraSettings settings_;
  FrameAssociator associator_;
  std::unique_ptr<ClockSync> clock_;
  ImageMessageEncoder encoder_;
  std::map<uint64_t, ArvBuffer*> held_;  // frames waiting for their edge
  uint64_t next_token_ = 0;

  std::atomic<int64_t> software_requests_{0};
  std::function<void(int64_t)> trigger_hook_;
  std::function<void(const EffectiveCameraSettings&)> on_connected_;
  int64_t next_software_trigger_mono_us_ = 0;

  // Watchdog: when a frame became due and nothing arrived since.
  int64_t frame_due_since_mono_us_ = -1;
  // Reconnect state.
  bool ever_connected_ = false;
  int64_t next_attempt_mono_us_ = 0;
  double backoff_s_ = 0;
  int64_t reconnect_attempts_ = 0;
  std::string disconnect_reason_;
  std::string last_error_;
  bool stopped_ = false;  // stop() was asked for: not a fault

  // Counters for STATUS.
  int64_t published_images_ = 0;
  int64_t published_triggers_ = 0;
  int64_t edges_received_ = 0;
  int64_t buffers_received_ = 0;
  int64_t buffers_incomplete_ = 0;
  int64_t dropped_unassociated_ = 0;
  int64_t reconnects_ = 0;
  int64_t disconnects_ = 0;
  int64_t software_triggers_sent_ = 0;
  int64_t frames_trigger_time_ = 0;
  int64_t frames_camera_clock_ = 0;
  int64_t frames_arrival_time_ = 0;
  StreamStatistics stats_before_;  // totals of streams closed by reconnects
};

}  // namespace nadir
