// Live mode over real LCM (udpm, only inside the private network namespace
// that launch_scripts' test runner creates): the same channels as the log,
// sensor times near the wall clock, STATUS and CONFIG from "sim".
#include <gtest/gtest.h>
#include <pthread.h>
#include <sched.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <map>
#include <thread>

#include "common/channels.h"
#include "common/lcm_bus.h"
#include "common/time_base.h"
#include "nadir/config_t.hpp"
#include "nadir/image_t.hpp"
#include "nadir/status_t.hpp"
#include "tests/common/test_support.h"

namespace nadir {
namespace {

TEST(LiveMode, PublishesEveryChannelInRealTime) {
  if (!nadir::testing::in_private_netns()) GTEST_SKIP() << "udpm only inside the private network namespace";
  // A 4 MB receive buffer, as the live default has: a 313 KB image does not
  // fit the kernel's default one.
  const std::string url = "udpm://239.255.76.67:7611?ttl=0&recv_buf_size=4194304";
  LcmBusOptions options;
  options.url = url;
  LcmBus bus(options);
  std::map<std::string, int> count;
  int64_t worst_latency_us = 0;
  int64_t earliest_image_us = INT64_MAX;
  std::string status_name, config_name;
  for (const char* ch : {channels::kCameraTrigger, channels::kIns, channels::kAltimeter, channels::kGroundTruth})
    bus.subscribe_raw(ch, [&](const std::string& c, const uint8_t*, size_t) { ++count[c]; });
  bus.subscribe<image_t>(channels::kCameraImage, [&](const image_t& img) {
    ++count[channels::kCameraImage];
    worst_latency_us = std::max(worst_latency_us, vehicle_time_now_us() - img.utime);
    earliest_image_us = std::min(earliest_image_us, img.utime);
  });
  bus.subscribe<status_t>(channels::kStatus, [&](const status_t& s) { status_name = s.name; });
  bus.subscribe<config_t>(channels::kConfig, [&](const config_t& c) { config_name = c.name; });

  const char* dir = std::getenv("NADIR_BIN_DIR");
  const std::string binary = std::string(dir ? dir : NADIR_BINARY_DIR "/bin") + "/nadir_sim";
  const int64_t vehicle_time_at_start_us = vehicle_time_now_us();
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    execl(binary.c_str(), binary.c_str(), "--profile", "demo", "--seed", "3", "--duration", "2", "--live", "--lcm-url",
          url.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  int status = 0;
  const int64_t start = monotonic_now_us();
  while (waitpid(child, &status, WNOHANG) == 0 && monotonic_now_us() - start < 60000000) bus.handle(50);
  for (int i = 0; i < 5; ++i) bus.handle(20);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0);
  EXPECT_EQ(config_name, "sim");
  EXPECT_EQ(status_name, "sim");
  EXPECT_EQ(count[channels::kCameraTrigger], 29);  // 14 Hz over [0, 2] s
  // Seed 3 drops no frame in these 2 s: every image arrives.
  EXPECT_EQ(count[channels::kCameraImage], 29);
  EXPECT_EQ(count[channels::kIns], 201);
  EXPECT_EQ(count[channels::kAltimeter], 21);
  // Images carry their (sensor) time on the live vehicle clock: none stamped
  // before the simulator was started, none received before its own time. How
  // late they arrive is a figure of the machine's load, not a pass/fail
  // (launch_scripts/latency.sh measures it); printed for the record.
  EXPECT_GE(earliest_image_us, vehicle_time_at_start_us);
  EXPECT_GE(worst_latency_us, 0);
  std::printf("worst image latency %.1f ms\n", worst_latency_us / 1e3);
}

// Runs a shell command; its stdout (give 2>&1 for stderr too) into *output,
// its wait status returned (-1 if it could not be started).
int run_command(const std::string& command, std::string* output) {
  FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) return -1;
  char buffer[512];
  while (std::fgets(buffer, sizeof buffer, pipe)) *output += buffer;
  return pclose(pipe);
}

// Whether this process may put a thread under SCHED_FIFO (root or
// CAP_SYS_NICE in the initial user namespace), tried on a throwaway thread.
bool fifo_permitted() {
  bool permitted = false;
  std::thread probe([&] {
    sched_param param{};
    param.sched_priority = 1;
    permitted = pthread_setschedparam(pthread_self(), SCHED_FIFO, &param) == 0;
  });
  probe.join();
  return permitted;
}

// --publish-rt-priority: where the platform allows it the publisher runs
// under SCHED_FIFO and says so; where it does not, the simulator stops at
// once with an error naming the option, never flying at ordinary priority
// as if it had been granted.
TEST(LiveMode, PublisherUnderRealTimePriorityOrAClearError) {
  if (!nadir::testing::in_private_netns()) GTEST_SKIP() << "udpm only inside the private network namespace";
  const char* dir = std::getenv("NADIR_BIN_DIR");
  const std::string binary = std::string(dir ? dir : NADIR_BINARY_DIR "/bin") + "/nadir_sim";
  const std::string command = binary +
                              " --profile demo --seed 3 --duration 1 --live --publish-rt-priority 7"
                              " --lcm-url 'udpm://239.255.76.67:7612?ttl=0' 2>&1";
  std::string output;
  const int status = run_command(command, &output);
  ASSERT_TRUE(WIFEXITED(status)) << output;
  if (fifo_permitted()) {
    EXPECT_EQ(WEXITSTATUS(status), 0) << output;
    EXPECT_NE(output.find("publisher under SCHED_FIFO 7, renderer at niceness 10"), std::string::npos) << output;
    EXPECT_NE(output.find("simulated in"), std::string::npos) << output;
  } else {
    EXPECT_EQ(WEXITSTATUS(status), 1) << output;
    EXPECT_NE(output.find("--publish-rt-priority 7: SCHED_FIFO not permitted"), std::string::npos) << output;
    EXPECT_EQ(output.find("simulated in"), std::string::npos) << output;  // it did not fly
  }
}

// The live-only scheduling options are refused, not ignored, when writing a log.
TEST(LiveMode, SchedulingOptionsNeedLiveMode) {
  const char* dir = std::getenv("NADIR_BIN_DIR");
  const std::string binary = std::string(dir ? dir : NADIR_BINARY_DIR "/bin") + "/nadir_sim";
  for (const std::string option : {"--publish-rt-priority 7", "--render-nice 5"}) {
    const std::string command =
        binary + " --profile demo --duration 1 --out /dev/null " + option + " 2>&1";
    std::string output;
    const int status = run_command(command, &output);
    ASSERT_TRUE(WIFEXITED(status)) << output;
    EXPECT_NE(WEXITSTATUS(status), 0) << option;
    EXPECT_NE(output.find(option.substr(0, option.find(' ')) + " requires --live"), std::string::npos) << output;
  }
}

}  // namespace
}  // namespace nadir
