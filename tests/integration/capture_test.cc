// lcm-logger captures 612x512 images at 14 Hz for 60 s over udpm (inside the
// private namespace) without losing one: nadir_log's count equals what was sent.
#include <gtest/gtest.h>

#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>

#include <chrono>
#include <cstdlib>
#include <thread>

#include "common/channels.h"
#include "common/lcm_bus.h"
#include "common/time_base.h"
#include "nadir/image_t.hpp"
#include "tests/common/test_support.h"
#include "tools/log/log_summary.h"

extern char** environ;

namespace nadir {
namespace {

TEST(Capture, LcmLoggerKeepsEveryImageAt14HzFor60s) {
  if (!testing::in_private_netns()) GTEST_SKIP() << "udpm runs only inside test.sh's private network namespace";
  testing::TempDir dir("capture");
  const std::string url = default_lcm_url();
  const std::string log = dir.file("capture.lcmlog");
  const std::string url_arg = "--lcm-url=" + url;
  const char* argv[] = {"lcm-logger", "--quiet", url_arg.c_str(), log.c_str(), nullptr};
  pid_t logger = 0;
  ASSERT_EQ(posix_spawnp(&logger, "lcm-logger", nullptr, nullptr, const_cast<char**>(argv), environ), 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(500));

  LcmBusOptions options;
  options.url = url;
  LcmBus bus(options);
  image_t image{};
  image.width = 612;
  image.height = 512;
  image.stride = 612;
  image.pixel_format = image_t::PIXEL_MONO8;
  image.size = 612 * 512;
  image.data.resize(image.size);
  const int frames = 14 * (std::getenv("NADIR_CAPTURE_SECONDS") ? std::atoi(std::getenv("NADIR_CAPTURE_SECONDS")) : 60);
  const auto start = std::chrono::steady_clock::now();
  for (int i = 0; i < frames; ++i) {
    std::this_thread::sleep_until(start + std::chrono::microseconds(static_cast<int64_t>(i * 1e6 / 14.0)));
    for (size_t k = 0; k < image.data.size(); k += 4096) image.data[k] = static_cast<uint8_t>(i + k);
    image.utime = vehicle_time_now_us();
    image.frame_counter = i;
    bus.publish(channels::kCameraImage, image);
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  kill(logger, SIGINT);
  int status = 0;
  waitpid(logger, &status, 0);

  const LogSummary summary = summarize_log(log);
  ASSERT_EQ(summary.channels.count(channels::kCameraImage), 1u);
  const ChannelSummary& images = summary.channels.at(channels::kCameraImage);
  EXPECT_EQ(images.messages, frames);
  EXPECT_EQ(images.type, "nadir.image_t");
  EXPECT_EQ(summary.corrupt_records, 0);
  EXPECT_NEAR(images.rate_hz(), 14.0, 0.2);
  std::printf("captured %lld of %d images, %.1f MB, %.2f Hz\n", static_cast<long long>(images.messages), frames,
              images.bytes / 1e6, images.rate_hz());
}

}  // namespace
}  // namespace nadir
