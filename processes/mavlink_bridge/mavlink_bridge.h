#pragma once
// The bridge's logic without any I/O. In: MAVLink bytes from the autopilot
// (with their arrival time on the vehicle time base) -> INS (ATTITUDE or
// ATTITUDE_QUATERNION), ALTIMETER (DISTANCE_SENSOR facing down) and truth
// (GLOBAL_POSITION_INT, GPS_RAW_INT) on the bus. Out: POSE from the bus ->
// VISION_POSITION_ESTIMATE / ODOMETRY / GPS_INPUT frames, HEARTBEAT and
// TIMESYNC on tick(), handed to `send`.
//
// Time: the autopilot stamps its messages with its boot time (time_boot_ms).
// ClockSync maps it onto the vehicle time base from samples stamped when the
// autopilot sent them: SYSTEM_TIME, TIMESYNC requests from the autopilot and
// its answers to ours (tc1). Attitude and range are not clock samples (they
// are stamped at measurement, sent later) and wait until the clock is valid.

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "common/bus.h"
#include "common/clock_sync.h"
#include "common/geodetic.h"
#include "common/status.h"
#include "nadir/pose_t.hpp"
#include "processes/mavlink_bridge/bridge_options.h"
#include "processes/mavlink_bridge/mavlink_frame.h"

namespace nadir::mavlink_bridge {

struct InputCounters {
  int64_t heartbeats = 0;
  int64_t attitude = 0;            // ATTITUDE / ATTITUDE_QUATERNION published as INS
  int64_t attitude_ignored = 0;    // the other attitude message than configured
  int64_t waiting_for_clock = 0;   // dropped before the clock estimate was valid
  int64_t bad_values = 0;          // non-finite or impossible (quaternion norm)
  int64_t distance = 0;            // published as ALTIMETER
  int64_t distance_ignored = 0;    // not facing down or another sensor id
  int64_t truth = 0;
  int64_t clock_samples = 0;       // SYSTEM_TIME, TIMESYNC
  int64_t timesync_answered = 0;   // requests from the autopilot answered
  int64_t other_system = 0;        // frames from systems other than the autopilot
  int64_t not_read = 0;            // known messages nadir only sends
};

struct OutputCounters {
  int64_t poses = 0;
  int64_t vision_position_estimate = 0;
  int64_t odometry = 0;
  int64_t gps_input = 0;
  int64_t heartbeat = 0;
  int64_t timesync = 0;
  int64_t resets = 0;   // estimator resets seen (reset_counter increments)
};

class MavlinkBridge {
 public:
  using Send = std::function<void(const std::vector<uint8_t>& frame)>;
  MavlinkBridge(const BridgeOptions& options, Bus& bus, Send send);

  // Bytes from the link; `datagram`: they are one whole UDP datagram. Returns
  // how many of the frames they held came from the autopilot (valid frames of
  // the autopilot's system, or its HEARTBEAT): the UDP server answers only a
  // sender with at least one.
  int on_bytes(const uint8_t* data, size_t size, int64_t arrival_us, double byte_time_us, bool datagram);
  void on_link_reopened();
  void on_pose(const pose_t& pose);
  // Periodic output (HEARTBEAT, TIMESYNC requests) due at vehicle time now_us.
  void tick(int64_t now_us);

  void report(StatusReport* report) const;
  int64_t rejected_frames() const { return parser_.counts().rejected_spans; }
  const mavlink::FrameCounts& frame_counts() const { return parser_.counts(); }
  const InputCounters& input() const { return in_; }
  const OutputCounters& output() const { return out_; }
  const ClockSyncState& clock_state() const { return clock_.state(); }
  int autopilot_system() const { return autopilot_sysid_; }

 private:
  // True when the frame came from the autopilot.
  bool handle(const mavlink::Frame& frame);
  void handle_from_autopilot(const mavlink::Frame& frame);
  void clock_sample(int64_t device_us, int64_t arrival_us);
  void on_attitude(uint32_t time_boot_ms, double roll, double pitch, double yaw, const float rates[3]);
  void on_distance(const mavlink::Frame& frame);
  void on_truth(const mavlink::Frame& frame);
  void on_timesync(const mavlink::Frame& frame);
  template <class M>
  void send(const M& msg);
  bool due(double rate_hz, int64_t utime, int64_t* last_us) const;

  BridgeOptions options_;
  Bus& bus_;
  Send send_;
  mavlink::FrameParser parser_;
  mavlink::FrameEncoder encoder_;
  ClockSync clock_;
  std::vector<mavlink::Frame> frames_;
  int autopilot_sysid_ = 0;  // 0 until heard (or configured)
  InputCounters in_;
  OutputCounters out_;
  // Output pacing (sensor time of the POSE last sent) and the reset counter.
  int64_t last_vpe_us_ = 0, last_odometry_us_ = 0, last_gps_input_us_ = 0;
  int64_t last_heartbeat_us_ = 0, last_timesync_us_ = 0;
  bool have_pose_ = false;
  int64_t last_frames_ = 0;
  bool last_initializing_ = false;
  uint8_t reset_counter_ = 0;
  GeodeticTrack gps_track_;  // POSE's path from the GPS_INPUT origin
  std::vector<int64_t> timesync_requests_ns_;  // ts1 of our recent requests
};

}  // namespace nadir::mavlink_bridge
