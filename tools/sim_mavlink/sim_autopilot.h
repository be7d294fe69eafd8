#pragma once
// The autopilot side of a MAVLink link, fed by the simulator: INS becomes
// ATTITUDE (or ATTITUDE_QUATERNION), ALTIMETER becomes DISTANCE_SENSOR facing
// down, all stamped with a boot time (vehicle time minus the start), with
// HEARTBEAT and SYSTEM_TIME at 1 Hz and TIMESYNC requests answered, as PX4 or
// ArduPilot do. What the companion sends back (VISION_POSITION_ESTIMATE,
// ODOMETRY, GPS_INPUT, HEARTBEAT) is parsed and counted.
// Sensor messages only: no I/O here (main.cc owns the sockets).

#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "nadir/altimeter_t.hpp"
#include "nadir/ins_t.hpp"
#include "processes/mavlink_bridge/mavlink_frame.h"

namespace nadir::sim_mavlink {

struct SimAutopilotOptions {
  bool quaternion = false;          // ATTITUDE_QUATERNION instead of ATTITUDE
  int system_id = 1;
  int component_id = 1;             // MAV_COMP_ID_AUTOPILOT1
  double min_distance_m = 0.2;      // DISTANCE_SENSOR limits reported
  double max_distance_m = 600.0;
};

struct CompanionCounts {
  std::map<std::string, int64_t> received;  // by message name
  int64_t rejected_spans = 0;
  int64_t timesync_answered = 0;
  uint8_t last_reset_counter = 0;
};

class SimAutopilot {
 public:
  using Send = std::function<void(const std::vector<uint8_t>& frame)>;
  SimAutopilot(const SimAutopilotOptions& options, int64_t boot_vehicle_us, Send send);

  void on_ins(const ins_t& ins);
  void on_altimeter(const altimeter_t& altimeter);
  // HEARTBEAT and SYSTEM_TIME when due at vehicle time now_us.
  void tick(int64_t now_us);
  // One datagram from the companion, received at vehicle time now_us.
  void on_datagram(const uint8_t* data, size_t size, int64_t now_us);

  const CompanionCounts& companion() const { return companion_; }
  int64_t sent() const { return sent_; }
  int64_t skipped_before_boot() const { return skipped_; }

 private:
  bool boot_ms(int64_t utime, uint32_t* ms);
  template <class M>
  void send(const M& msg) {
    send_(encoder_.encode(msg));
    ++sent_;
  }

  SimAutopilotOptions options_;
  int64_t boot_us_;
  Send send_;
  mavlink::FrameEncoder encoder_;
  mavlink::FrameParser parser_;
  int64_t last_second_us_ = 0;
  int64_t sent_ = 0;
  int64_t skipped_ = 0;
  CompanionCounts companion_;
};

}  // namespace nadir::sim_mavlink
