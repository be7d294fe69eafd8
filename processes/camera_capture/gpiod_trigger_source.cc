#include "processes/camera_capture/gpiod_trigger_source.h"

#include <gpiod.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

#include "common/time_base.h"
#include "nadir/trigger_t.hpp"

namespace nadir {

namespace {

std::runtime_error gpio_error(const GpiodTriggerOptions& o, const std::string& what) {
  return std::runtime_error("GPIO trigger " + o.chip + ":" + std::to_string(o.line) + ": " + what + ": " +
                            std::strerror(errno));
}

}  // namespace

GpiodTriggerSource::GpiodTriggerSource(const GpiodTriggerOptions& options) : options_(options) {
  chip_ = gpiod_chip_open_lookup(options_.chip.c_str());
  if (chip_ == nullptr) throw gpio_error(options_, "cannot open the chip");
  line_ = gpiod_chip_get_line(chip_, static_cast<unsigned>(options_.line));
  if (line_ == nullptr) {
    gpiod_chip_close(chip_);
    throw gpio_error(options_, "no such line");
  }
  int rc = -1;
  if (options_.edge == "rising") {
    rc = gpiod_line_request_rising_edge_events(line_, options_.consumer.c_str());
  } else if (options_.edge == "falling") {
    rc = gpiod_line_request_falling_edge_events(line_, options_.consumer.c_str());
  } else if (options_.edge == "both") {
    rc = gpiod_line_request_both_edges_events(line_, options_.consumer.c_str());
  } else {
    gpiod_chip_close(chip_);
    throw std::runtime_error("GPIO trigger: edge '" + options_.edge + "' is not rising, falling or both");
  }
  if (rc < 0) {
    gpiod_chip_close(chip_);
    throw gpio_error(options_, "cannot request " + options_.edge + " edge events");
  }
}

GpiodTriggerSource::~GpiodTriggerSource() {
  if (line_ != nullptr) gpiod_line_release(line_);
  if (chip_ != nullptr) gpiod_chip_close(chip_);
}

void GpiodTriggerSource::poll(int timeout_ms, std::vector<TriggerEdge>* edges) {
  timespec timeout{timeout_ms / 1000, static_cast<long>(timeout_ms % 1000) * 1000000L};
  int waited = gpiod_line_event_wait(line_, &timeout);
  if (waited < 0) throw gpio_error(options_, "waiting for events failed");
  while (waited > 0) {
    gpiod_line_event events[16];
    const int n = gpiod_line_event_read_multiple(line_, events, 16);
    if (n < 0) throw gpio_error(options_, "reading events failed");
    for (int i = 0; i < n; ++i) {
      TriggerEdge e;
      e.sequence = next_sequence_++;
      // libgpiod 1.6 with kernels >= 5.7 stamps events on CLOCK_MONOTONIC.
      e.device_us = static_cast<int64_t>(events[i].ts.tv_sec) * 1000000 + events[i].ts.tv_nsec / 1000;
      e.vehicle_us = monotonic_to_vehicle_us(e.device_us);
      e.edge = events[i].event_type == GPIOD_LINE_EVENT_RISING_EDGE ? trigger_t::EDGE_RISING : trigger_t::EDGE_FALLING;
      edges->push_back(e);
    }
    timespec zero{0, 0};
    waited = gpiod_line_event_wait(line_, &zero);
    if (waited < 0) throw gpio_error(options_, "waiting for events failed");
  }
}

std::string GpiodTriggerSource::describe() const {
  return "gpiod " + options_.chip + ":" + std::to_string(options_.line) + " " + options_.edge;
}

}  // namespace nadir
