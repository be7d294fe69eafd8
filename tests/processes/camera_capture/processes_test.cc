// The two executables as a user runs them, over real LCM (udpm on loopback)
// inside a private network namespace: nadir_fake_camera serves the pattern,
// nadir_camera_capture captures it; CONFIG carries the read-back settings,
// STATUS comes at 1 Hz, SIGTERM stops both cleanly.

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <string>
#include <thread>
#include <vector>

#include "common/channels.h"
#include "common/lcm_bus.h"
#include "common/time_base.h"
#include "nadir/config_t.hpp"
#include "nadir/image_t.hpp"
#include "nadir/status_t.hpp"
#include "tests/common/test_support.h"

namespace nadir {
namespace {

std::string bin(const std::string& name) {
  const char* dir = std::getenv("NADIR_BIN_DIR");
  return std::string(dir != nullptr ? dir : NADIR_BINARY_DIR "/bin") + "/" + name;
}

pid_t spawn(const std::vector<std::string>& args) {
  const pid_t pid = fork();
  if (pid == 0) {
    std::vector<char*> argv;
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    execv(argv[0], argv.data());
    _exit(127);
  }
  return pid;
}

int stop(pid_t pid) {
  kill(pid, SIGTERM);
  int status = 0;
  waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

TEST(CameraCaptureProcesses, HelpWorks) {
  for (const char* name : {"nadir_camera_capture", "nadir_fake_camera"}) {
    const std::string command = bin(name) + " --help > /dev/null";
    EXPECT_EQ(std::system(command.c_str()), 0) << command;
  }
}

TEST(CameraCaptureProcesses, CaptureFromFakeCameraOverUdpm) {
  if (!testing::in_private_netns()) GTEST_SKIP() << "needs NADIR_IN_NETNS=1 (udpm and a fake camera on lo)";
  const std::string url = "udpm://239.255.76.67:7671?ttl=0&recv_buf_size=4194304";
  LcmBusOptions options;
  options.url = url;
  LcmBus bus(options);
  std::vector<image_t> images;
  std::vector<status_t> statuses;
  std::vector<config_t> configs;
  bus.subscribe<image_t>(channels::kCameraImage, [&](const image_t& m) { images.push_back(m); });
  bus.subscribe<status_t>(channels::kStatus, [&](const status_t& m) {
    if (m.name == "camera_capture") statuses.push_back(m);
  });
  bus.subscribe<config_t>(channels::kConfig, [&](const config_t& m) { configs.push_back(m); });

  const pid_t fake = spawn({bin("nadir_fake_camera"), "--serial", "PROC1"});
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  const pid_t capture = spawn({bin("nadir_camera_capture"), "--lcm-url", url, "--camera-id", "Aravis-Fake-PROC1",
                               "--trigger-input", "none", "--trigger-mode", "free_run"});
  const int64_t end = monotonic_now_us() + s_to_us(4.0);
  while (monotonic_now_us() < end) bus.handle(50);
  const int capture_exit = stop(capture);
  const int64_t drain = monotonic_now_us() + s_to_us(0.5);
  while (monotonic_now_us() < drain) bus.handle(50);
  EXPECT_EQ(stop(fake), 0);
  EXPECT_EQ(capture_exit, 0);

  ASSERT_FALSE(configs.empty());
  EXPECT_NE(configs.front().yaml.find("effective"), std::string::npos);
  EXPECT_NE(configs.front().yaml.find("Aravis-Fake-PROC1"), std::string::npos);
  EXPECT_GE(statuses.size(), 2u);
  ASSERT_FALSE(statuses.empty());
  EXPECT_EQ(statuses.back().state, status_t::STATE_STOPPING);
  // 14 Hz free run for ~3 s after connecting.
  double published = 0;
  for (int i = 0; i < statuses.back().num_counters; ++i) {
    if (statuses.back().counter_names[i] == "images_published") published = statuses.back().counter_values[i];
  }
  EXPECT_GE(published, 25.0);
  EXPECT_GE(images.size(), 25u);
  ASSERT_FALSE(images.empty());
  EXPECT_EQ(images.back().width, 612);
  EXPECT_EQ(images.back().height, 512);
  EXPECT_NE(images.back().time_quality, image_t::TIME_TRIGGER);  // no GPIO: camera clock or arrival
  EXPECT_EQ(images.back().trigger_sequence, -1);
}

}  // namespace
}  // namespace nadir
