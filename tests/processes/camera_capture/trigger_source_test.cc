// Trigger sources: the scripted one (tests, HIL) and the libgpiod one's
// error path (this machine has no GPIO chip; on the vehicle it opens one).

#include <gtest/gtest.h>

#include <string>
#include <thread>
#include <vector>

#include "processes/camera_capture/gpiod_trigger_source.h"
#include "processes/camera_capture/scripted_trigger_source.h"

namespace nadir {
namespace {

TEST(TriggerSource, ScriptedEdgesArriveInOrderAcrossThreads) {
  ScriptedTriggerSource source;
  std::thread producer([&] {
    for (int i = 0; i < 50; ++i) source.emit(1000 + i * 71429);
  });
  std::vector<TriggerEdge> edges;
  while (edges.size() < 50) source.poll(100, &edges);
  producer.join();
  for (int i = 0; i < 50; ++i) {
    EXPECT_EQ(edges[i].sequence, i);
    EXPECT_EQ(edges[i].vehicle_us, 1000 + i * 71429);
  }
  std::vector<TriggerEdge> none;
  source.poll(0, &none);
  EXPECT_TRUE(none.empty());
}

TEST(TriggerSource, MissingGpioChipIsAClearError) {
  GpiodTriggerOptions options;
  options.chip = "nadir-no-such-gpiochip";
  options.line = 17;
  try {
    GpiodTriggerSource source(options);
    FAIL() << "opened a GPIO chip that does not exist";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("nadir-no-such-gpiochip:17"), std::string::npos) << what;
    EXPECT_NE(what.find("cannot open the chip"), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace nadir
