#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "common/channels.h"
#include "common/log_holes.h"
#include "common/message_guard.h"
#include "nadir/status_t.hpp"

namespace nadir {
namespace {

void add_status(LogHoleFinder* finder, const std::string& name, int64_t logged_us) {
  status_t s{};
  s.utime = logged_us;
  s.name = name;
  const std::vector<uint8_t> bytes = encode_message(s);
  LogEvent e;
  e.channel = channels::kStatus;
  e.timestamp = logged_us;
  e.data = bytes.data();
  e.size = bytes.size();
  finder->add(e);
}

// Six processes send STATUS at 1 Hz within 0.15 s of each other (0.85 s
// between bursts, more than 5 mean intervals of the channel): no hole. One of
// them stopped for 8 s is one (a 1 Hz stream's hole is longer than 5 of its
// intervals), named after it; an undecodable STATUS is
// nobody's heartbeat.
TEST(LogHoles, StatusIsJudgedPerProcess) {
  const std::vector<std::string> names = {"sim", "sim_mavlink", "mavlink_bridge", "tracker", "vo_solver", "yaw_fusion"};
  LogHoleFinder finder;
  const int64_t t0 = 1767225600000000;
  for (int second = 0; second < 60; ++second) {
    for (size_t k = 0; k < names.size(); ++k) {
      if (names[k] == "vo_solver" && second >= 30 && second < 38) continue;
      add_status(&finder, names[k], t0 + second * 1000000 + static_cast<int64_t>(k) * 30000);
    }
    const uint8_t garbage[12] = {1, 2, 3};
    LogEvent e;
    e.channel = channels::kStatus;
    e.timestamp = t0 + second * 1000000 + 500000;
    e.data = garbage;
    e.size = sizeof garbage;
    if (second % 10 == 0) finder.add(e);
  }
  const std::vector<LogHole> holes = finder.holes();
  ASSERT_EQ(holes.size(), 1u) << format_log_holes(holes);
  EXPECT_EQ(holes[0].channel, "STATUS from vo_solver");
  EXPECT_NEAR(holes[0].seconds(), 9.0, 1e-9);
  EXPECT_EQ(holes[0].expected_messages, 6);  // at the mean interval, which the hole lengthens
}

}  // namespace
}  // namespace nadir
