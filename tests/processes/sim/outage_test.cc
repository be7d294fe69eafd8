// Outages cut into a flight change what they cover and nothing else: every
// message outside the windows is byte for byte the message of the same flight
// without them, the altimeter answers VALID_NO_RETURN inside its window, INS
// and camera stop, and a texture outage flattens the image to the set contrast.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include "common/channels.h"
#include "common/message_guard.h"
#include "nadir/altimeter_t.hpp"
#include "nadir/image_t.hpp"
#include "processes/sim/sensor_outage.h"
#include "processes/sim/simulator.h"
#include "sim_test_support.h"

namespace nadir::sim {
namespace {

using Key = std::tuple<std::string, int64_t, int>;  // channel, utime, occurrence

std::map<Key, SimEvent> fly(const std::vector<SensorOutage>& outages, bool images, double duration_s) {
  SimulatorOptions options;
  options.seed = 5;
  options.duration_s = duration_s;
  options.render_images = images;
  options.outages = outages;
  Simulator sim(testing::profile("demo"), testing::default_camera(), testing::sensor_set("standard"), options);
  std::map<Key, SimEvent> events;
  std::map<std::pair<std::string, int64_t>, int> seen;
  SimEvent e;
  while (sim.next(&e)) {
    if (e.channel == channels::kConfig) continue;  // names the outages
    const int n = seen[{e.channel, e.utime}]++;
    events[{e.channel, e.utime, n}] = e;
  }
  return events;
}

double flight_s(int64_t utime) { return static_cast<double>(utime - kLogEpochUs) * 1e-6; }

TEST(SensorOutage, ParsesAndNamesBadText) {
  const SensorOutage o = SensorOutage::parse("texture:40:10:0.05");
  EXPECT_EQ(o.kind, SensorOutage::Kind::kTexture);
  EXPECT_DOUBLE_EQ(o.start_s, 40.0);
  EXPECT_DOUBLE_EQ(o.duration_s, 10.0);
  EXPECT_DOUBLE_EQ(o.contrast, 0.05);
  EXPECT_TRUE(o.covers(40.0));
  EXPECT_FALSE(o.covers(50.0));
  for (const char* bad : {"radar:1:2", "altimeter:1", "altimeter:x:2", "altimeter:1:0", "ins:1:2:0.5",
                          "texture:1:2:3", "altimeter:-1:2"}) {
    try {
      SensorOutage::parse(bad);
      ADD_FAILURE() << bad << " accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(bad), std::string::npos) << e.what();
    }
  }
}

TEST(SensorOutage, ChangesOnlyWhatItCovers) {
  const std::map<Key, SimEvent> clean = fly({}, false, 6.0);
  const std::vector<SensorOutage> outages = {SensorOutage::parse("altimeter:1:2"), SensorOutage::parse("ins:3.5:1")};
  const std::map<Key, SimEvent> cut = fly(outages, false, 6.0);
  int no_return = 0;
  int withheld = 0;
  for (const auto& [key, event] : clean) {
    const std::string& channel = std::get<0>(key);
    const double t = flight_s(std::get<1>(key));
    const auto it = cut.find(key);
    if (channel == channels::kIns && outages[1].covers(t)) {
      EXPECT_EQ(it, cut.end()) << "INS at " << t << " s published in the outage";
      ++withheld;
      continue;
    }
    ASSERT_NE(it, cut.end()) << channel << " at " << t << " s missing";
    if (channel == channels::kAltimeter && outages[0].covers(t)) {
      altimeter_t a;
      std::string reason;
      ASSERT_TRUE(decode_message(it->second.data.data(), it->second.data.size(), &a, &reason)) << reason;
      EXPECT_EQ(a.validity, altimeter_t::VALID_NO_RETURN);
      ++no_return;
      continue;
    }
    EXPECT_EQ(it->second.data, event.data) << channel << " at " << t << " s differs outside the outages";
  }
  EXPECT_EQ(no_return, 20);  // 10 Hz for 2 s
  EXPECT_EQ(withheld, 100);  // 100 Hz for 1 s
  EXPECT_EQ(cut.size(), clean.size() - 100);
}

TEST(SensorOutage, TextureOutageFlattensTheImage) {
  const std::map<Key, SimEvent> clean = fly({}, true, 4.6);
  const std::map<Key, SimEvent> cut = fly({SensorOutage::parse("texture:2.02:0.5:0.03"),
                                           SensorOutage::parse("camera:4.02:0.5")}, true, 4.6);
  int flattened = 0;
  int missing = 0;
  for (const auto& [key, event] : clean) {
    if (std::get<0>(key) != channels::kCameraImage) continue;
    const double t = flight_s(std::get<1>(key));
    const auto it = cut.find(key);
    if (t >= 4.02 && t < 4.52) {  // frame times are 1/14 s apart: no frame near an edge
      EXPECT_EQ(it, cut.end());
      ++missing;
      continue;
    }
    ASSERT_NE(it, cut.end());
    if (t < 2.02 || t >= 2.52) {
      EXPECT_EQ(it->second.data, event.data);
      continue;
    }
    image_t a, b;
    std::string reason;
    ASSERT_TRUE(decode_message(event.data.data(), event.data.size(), &a, &reason));
    ASSERT_TRUE(decode_message(it->second.data.data(), it->second.data.size(), &b, &reason));
    const auto [lo_a, hi_a] = std::minmax_element(a.data.begin(), a.data.end());
    const auto [lo_b, hi_b] = std::minmax_element(b.data.begin(), b.data.end());
    EXPECT_LE(*hi_b - *lo_b, 0.03 * (*hi_a - *lo_a) + 1.0);
    ++flattened;
  }
  EXPECT_GE(flattened, 6);  // 14 Hz for 0.5 s, less a dropped frame
  EXPECT_GE(missing, 6);
}

}  // namespace
}  // namespace nadir::sim
