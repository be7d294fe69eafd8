#include <gtest/gtest.h>

#include <climits>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "common/lcm_bus.h"
#include "common/message_guard.h"
#include "nadir/altimeter_t.hpp"
#include "nadir/config_t.hpp"
#include "nadir/ground_truth_t.hpp"
#include "nadir/image_t.hpp"
#include "nadir/ins_t.hpp"
#include "nadir/pose_t.hpp"
#include "nadir/status_t.hpp"
#include "nadir/tracks_t.hpp"
#include "nadir/trigger_t.hpp"
#include "nadir/vo_delta_t.hpp"

namespace nadir {
namespace {

image_t sample_image() {
  image_t m{};
  m.utime = 1000;
  m.width = 4;
  m.height = 3;
  m.stride = 4;
  m.pixel_format = image_t::PIXEL_MONO8;
  m.size = 12;
  m.data.assign(12, 7);
  return m;
}

tracks_t sample_tracks() {
  tracks_t m{};
  m.utime = 2000;
  m.num_tracks = 3;
  m.track_id = {1, 2, 3};
  m.age = {1, 1, 2};
  m.prev_px.assign(3, std::vector<float>{1.0f, 2.0f});
  m.curr_px.assign(3, std::vector<float>{1.5f, 2.5f});
  m.prev_norm.assign(3, std::vector<double>{0.1, 0.2});
  m.curr_norm.assign(3, std::vector<double>{0.15, 0.25});
  return m;
}

status_t sample_status() {
  status_t m{};
  m.name = "tracker";
  m.detail = "ok";
  m.num_counters = 2;
  m.counter_names = {"a", "bb"};
  m.counter_values = {1.0, 2.0};
  return m;
}

config_t sample_config() {
  config_t m{};
  m.name = "vo_solver";
  m.source = "config/default.yaml";
  m.yaml = "a: 1\n";
  return m;
}

vo_delta_t sample_delta() {
  vo_delta_t m{};
  m.utime = 3000;
  m.variant = "paper";
  return m;
}

// Every way of corrupting one message: a 32-bit value that a length field
// could hold (negative, zero, huge, one past the bytes) written at every byte
// offset, every truncation, and random bit flips. The guard must decide each
// without throwing, and accept only messages that decode to exactly their
// bytes.
template <class Msg>
void expect_every_corruption_is_decided(const Msg& sample, int* rejected) {
  const std::vector<uint8_t> good = encode_message(sample);
  Msg out;
  std::string reason;
  ASSERT_TRUE(decode_message(good.data(), good.size(), &out, &reason)) << reason;
  const int32_t values[] = {-1, INT32_MIN, INT32_MAX, 0, static_cast<int32_t>(good.size()) + 1, 0x10000000};
  auto check = [&](const std::vector<uint8_t>& bytes) {
    Msg msg;
    std::string why;
    bool ok = false;
    ASSERT_NO_THROW(ok = decode_message(bytes.data(), bytes.size(), &msg, &why));
    if (ok) {
      EXPECT_EQ(msg.getEncodedSize(), static_cast<int>(bytes.size()));
    } else {
      EXPECT_FALSE(why.empty());
      ++*rejected;
    }
  };
  for (size_t offset = 0; offset + 4 <= good.size(); ++offset) {
    for (const int32_t v : values) {
      std::vector<uint8_t> bytes = good;
      const uint32_t u = static_cast<uint32_t>(v);
      for (int i = 0; i < 4; ++i) bytes[offset + i] = static_cast<uint8_t>(u >> (24 - 8 * i));
      check(bytes);
    }
  }
  for (size_t length = 0; length < good.size(); ++length) {
    check(std::vector<uint8_t>(good.begin(), good.begin() + static_cast<std::ptrdiff_t>(length)));
  }
  std::mt19937 rng(7);
  for (int i = 0; i < 2000; ++i) {
    std::vector<uint8_t> bytes = good;
    const int flips = 1 + static_cast<int>(rng() % 4);
    for (int f = 0; f < flips; ++f) bytes[rng() % bytes.size()] ^= static_cast<uint8_t>(1u << (rng() % 8));
    check(bytes);
  }
}

TEST(MessageGuard, EveryCorruptionOfEveryTypeIsDecidedWithoutThrowing) {
  int rejected = 0;
  expect_every_corruption_is_decided(sample_image(), &rejected);
  expect_every_corruption_is_decided(sample_tracks(), &rejected);
  expect_every_corruption_is_decided(sample_status(), &rejected);
  expect_every_corruption_is_decided(sample_config(), &rejected);
  expect_every_corruption_is_decided(sample_delta(), &rejected);
  expect_every_corruption_is_decided(ins_t{}, &rejected);
  expect_every_corruption_is_decided(altimeter_t{}, &rejected);
  expect_every_corruption_is_decided(pose_t{}, &rejected);
  expect_every_corruption_is_decided(ground_truth_t{}, &rejected);
  expect_every_corruption_is_decided(trigger_t{}, &rejected);
  EXPECT_GT(rejected, 1000);
}

// Writes a big-endian int32 into an encoded message.
void put_i32(std::vector<uint8_t>* bytes, size_t offset, int32_t v) {
  const uint32_t u = static_cast<uint32_t>(v);
  for (int i = 0; i < 4; ++i) (*bytes)[offset + i] = static_cast<uint8_t>(u >> (24 - 8 * i));
}

TEST(MessageGuard, NegativeAndHugeCountsAreNamed) {
  // image_t.size sits after 4 int64, 3 int32, 2 int8 and 2 float: offset 8 + 54.
  std::vector<uint8_t> image = encode_message(sample_image());
  std::string reason;
  image_t img;
  put_i32(&image, 62, -1);
  EXPECT_FALSE(decode_message(image.data(), image.size(), &img, &reason));
  EXPECT_NE(reason.find("image_t.size is negative"), std::string::npos) << reason;
  put_i32(&image, 62, INT32_MAX);
  EXPECT_FALSE(decode_message(image.data(), image.size(), &img, &reason));
  EXPECT_NE(reason.find("image_t.size 2147483647 declares"), std::string::npos) << reason;

  // tracks_t.num_tracks: after 3 int64 and 3 int32: offset 8 + 36.
  std::vector<uint8_t> tracks = encode_message(sample_tracks());
  tracks_t t;
  put_i32(&tracks, 44, -1);
  EXPECT_FALSE(decode_message(tracks.data(), tracks.size(), &t, &reason));
  EXPECT_NE(reason.find("tracks_t.num_tracks is negative"), std::string::npos) << reason;

  ins_t ins;
  EXPECT_FALSE(decode_message(image.data(), image.size(), &ins, &reason));
  EXPECT_NE(reason.find("fingerprint"), std::string::npos) << reason;
}

// A process's bus survives every hostile message and keeps delivering.
TEST(MessageGuard, BusCountsHostileMessagesAndDeliversTheNextGoodOne) {
  LcmBusOptions options;
  options.url = "memq://";
  LcmBus bus(options);
  int images = 0, tracks = 0;
  bus.subscribe<image_t>("IMG", [&](const image_t&) { ++images; });
  bus.subscribe<tracks_t>("TRK", [&](const tracks_t&) { ++tracks; });
  std::vector<uint8_t> image = encode_message(sample_image());
  std::vector<uint8_t> track = encode_message(sample_tracks());
  for (const int32_t v : {-1, INT32_MAX, INT32_MIN, 100000}) {
    std::vector<uint8_t> bad_image = image, bad_tracks = track;
    put_i32(&bad_image, 62, v);
    put_i32(&bad_tracks, 44, v);
    bus.publish_raw("IMG", bad_image.data(), bad_image.size());
    bus.publish_raw("TRK", bad_tracks.data(), bad_tracks.size());
  }
  bus.publish_raw("IMG", image.data(), image.size());
  bus.publish_raw("TRK", track.data(), track.size());
  for (int k = 0; k < 20; ++k) bus.handle(0);
  EXPECT_EQ(images, 1);
  EXPECT_EQ(tracks, 1);
  EXPECT_EQ(bus.error_counts().malformed, 8);
  EXPECT_EQ(bus.error_counts().handler_errors, 0);
  EXPECT_NE(bus.error_counts().last_error.find("malformed message on TRK"), std::string::npos);
}

}  // namespace
}  // namespace nadir
