#pragma once
// A bridge on a real memq:// LCM bus with everything it publishes collected.

#include <memory>
#include <string>
#include <vector>

#include "common/channels.h"
#include "common/lcm_bus.h"
#include "nadir/altimeter_t.hpp"
#include "nadir/ins_t.hpp"
#include "nadir/status_t.hpp"
#include "processes/ins_bridge/bridge_options.h"

namespace nadir::ins_bridge::testing {

// Options for tests: devices named but unused unless a runner opens them.
inline BridgeOptions test_options() {
  BridgeOptions o;
  o.ins.serial.device = "/nonexistent/ins";
  o.ins.serial.baud = 230400;
  o.altimeter.serial.device = "/nonexistent/alt";
  o.altimeter.serial.baud = 115200;
  return o;
}

struct Collected {
  std::vector<ins_t> ins;
  std::vector<altimeter_t> altimeter;
  std::vector<status_t> status;
};

inline std::unique_ptr<LcmBus> memq_bus(Collected* out) {
  LcmBusOptions options;
  options.url = "memq://";
  options.queue_capacity = 100000;
  auto bus = std::make_unique<LcmBus>(options);
  bus->subscribe<ins_t>(channels::kIns, [out](const ins_t& m) { out->ins.push_back(m); });
  bus->subscribe<altimeter_t>(channels::kAltimeter, [out](const altimeter_t& m) { out->altimeter.push_back(m); });
  bus->subscribe<status_t>(channels::kStatus, [out](const status_t& m) { out->status.push_back(m); });
  return bus;
}

// Delivers everything queued on a memq bus.
inline void drain(LcmBus& bus) {
  while (bus.handle(0) > 0) {
  }
}

inline double counter(const status_t& s, const std::string& name) {
  for (int i = 0; i < s.num_counters; ++i)
    if (s.counter_names[static_cast<size_t>(i)] == name) return s.counter_values[static_cast<size_t>(i)];
  return -1;
}

}  // namespace nadir::ins_bridge::testing
