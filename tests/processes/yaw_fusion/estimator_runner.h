#pragma once
// Runs a YawFusionEstimator over messages in arrival order (estimator and
// coasting tests).

#include <gtest/gtest.h>

#include <vector>

#include "common/channels.h"
#include "processes/yaw_fusion/yaw_fusion_estimator.h"
#include "synthetic_flight.h"

namespace nadir::test {

inline std::vector<pose_t> run(YawFusionEstimator& estimator, const std::vector<TimedMessage>& messages) {
  std::vector<pose_t> poses;
  auto append = [&](std::vector<pose_t> more) { poses.insert(poses.end(), more.begin(), more.end()); };
  for (const TimedMessage& m : messages) {
    if (m.channel == channels::kVoDelta) {
      vo_delta_t msg;
      EXPECT_GT(msg.decode(m.bytes.data(), 0, static_cast<int>(m.bytes.size())), 0);
      append(estimator.add_vo_delta(msg));
    } else if (m.channel == channels::kIns) {
      ins_t msg;
      EXPECT_GT(msg.decode(m.bytes.data(), 0, static_cast<int>(m.bytes.size())), 0);
      append(estimator.add_ins(msg));
    } else if (m.channel == channels::kAltimeter) {
      altimeter_t msg;
      EXPECT_GT(msg.decode(m.bytes.data(), 0, static_cast<int>(m.bytes.size())), 0);
      append(estimator.add_altimeter(msg));
    } else if (m.channel == channels::kVoGround) {
      ground_points_t msg;
      EXPECT_GT(msg.decode(m.bytes.data(), 0, static_cast<int>(m.bytes.size())), 0);
      estimator.add_ground_points(msg);
    } else if (m.channel == channels::kMapFix) {
      map_fix_t msg;
      EXPECT_GT(msg.decode(m.bytes.data(), 0, static_cast<int>(m.bytes.size())), 0);
      estimator.add_map_fix(msg);
    }
  }
  return poses;
}

// The whole flight with the default latencies (VO 80 ms, INS 2 ms, altimeter 5 ms).
inline std::vector<pose_t> run_flight(const SyntheticFlight& flight, const YawFusionOptions& options,
                                      YawFusionCounters* counters = nullptr) {
  YawFusionEstimator estimator(options);
  auto poses = run(estimator, arrival_order(flight, 80'000, 2'000, 5'000));
  if (counters != nullptr) *counters = estimator.counters();
  return poses;
}

}  // namespace nadir::test
