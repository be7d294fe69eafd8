#pragma once
// Trigger edges from a GPIO input through libgpiod (v1 API). The kernel
// timestamps line events on CLOCK_MONOTONIC when the edge interrupt fires, so
// the edge time does not depend on when this process gets to read it; it is
// mapped to the vehicle time base with monotonic_to_vehicle_us.

#include <string>

#include "processes/camera_capture/trigger_source.h"

struct gpiod_chip;
struct gpiod_line;

namespace nadir {

struct GpiodTriggerOptions {
  std::string chip = "gpiochip0";  // name, path or number (gpiod_chip_open_lookup)
  int line = 0;                    // line offset on the chip
  std::string edge = "rising";     // rising | falling | both
  std::string consumer = "nadir_camera_capture";
};

class GpiodTriggerSource : public TriggerSource {
 public:
  // Throws std::runtime_error naming chip and line when they cannot be opened.
  explicit GpiodTriggerSource(const GpiodTriggerOptions& options);
  ~GpiodTriggerSource() override;
  GpiodTriggerSource(const GpiodTriggerSource&) = delete;
  GpiodTriggerSource& operator=(const GpiodTriggerSource&) = delete;

  void poll(int timeout_ms, std::vector<TriggerEdge>* edges) override;
  std::string describe() const override;

 private:
  GpiodTriggerOptions options_;
  gpiod_chip* chip_ = nullptr;
  gpiod_line* line_ = nullptr;
  int64_t next_sequence_ = 0;
};

}  // namespace nadir
