#pragma once
// Where trigger edges come from: a GPIO line (libgpiod), a script (tests), or
// nothing (no GPIO: frames are timed by the camera clock instead). Every edge
// carries its device timestamp and the same instant on the vehicle time base.

#include <cstdint>
#include <string>
#include <vector>

namespace nadir {

struct TriggerEdge {
  int64_t sequence = 0;    // edges seen since the source opened, from 0
  int64_t device_us = 0;   // raw timestamp (CLOCK_MONOTONIC for libgpiod)
  int64_t vehicle_us = 0;  // the same instant on the vehicle time base
  int8_t edge = 1;         // trigger_t::EDGE_RISING / EDGE_FALLING
};

class TriggerSource {
 public:
  virtual ~TriggerSource() = default;
  // Appends the edges that arrived since the last call, waiting up to
  // timeout_ms for the first one. Throws std::runtime_error naming the device
  // when it fails.
  virtual void poll(int timeout_ms, std::vector<TriggerEdge>* edges) = 0;
  // "gpiod gpiochip0:17 rising", "scripted", ...
  virtual std::string describe() const = 0;
};

}  // namespace nadir
