#include "tools/hostile/hostile_messages.h"

#include <cmath>
#include <limits>

#include "common/channels.h"
#include "nadir/altimeter_t.hpp"
#include "nadir/config_t.hpp"
#include "nadir/image_t.hpp"
#include "nadir/ins_t.hpp"
#include "nadir/status_t.hpp"
#include "nadir/tracks_t.hpp"
#include "nadir/vo_delta_t.hpp"

namespace nadir {
namespace {

constexpr int64_t kSecond = 1000000;

template <class Msg>
std::vector<uint8_t> encode(const Msg& msg) {
  std::vector<uint8_t> bytes(static_cast<size_t>(msg.getEncodedSize()));
  msg.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  return bytes;
}

void put_i32(std::vector<uint8_t>* bytes, size_t offset, int32_t v) {
  const uint32_t u = static_cast<uint32_t>(v);
  for (int i = 0; i < 4; ++i) (*bytes)[offset + i] = static_cast<uint8_t>(u >> (24 - 8 * i));
}

ins_t ins(int64_t utime, double attitude) {
  ins_t m{};
  m.utime = utime;
  m.device_utime = utime;
  m.roll = m.pitch = m.yaw = attitude;
  m.flags = ins_t::FLAG_ALIGNED | ins_t::FLAG_SOLUTION_GOOD;
  return m;
}

altimeter_t altimeter(int64_t utime, double range) {
  altimeter_t m{};
  m.utime = utime;
  m.range_m = range;
  m.beam_body[2] = 1.0;
  m.validity = altimeter_t::VALID_OK;
  return m;
}

tracks_t tracks(int64_t utime, double value, int n = 20) {
  tracks_t m{};
  m.utime = utime;
  m.prev_utime = utime - 71429;
  m.width = 612;
  m.height = 512;
  m.num_tracks = n;
  m.track_id.resize(static_cast<size_t>(n));
  m.age.assign(static_cast<size_t>(n), 3);
  m.prev_px.assign(static_cast<size_t>(n), std::vector<float>(2, static_cast<float>(value)));
  m.curr_px.assign(static_cast<size_t>(n), std::vector<float>(2, static_cast<float>(value)));
  m.prev_norm.assign(static_cast<size_t>(n), std::vector<double>(2, value));
  m.curr_norm.assign(static_cast<size_t>(n), std::vector<double>(2, value));
  for (int i = 0; i < n; ++i) m.track_id[static_cast<size_t>(i)] = 900000 + i;
  return m;
}

image_t image(int64_t utime, int width, int height) {
  image_t m{};
  m.utime = utime;
  m.trigger_utime = utime;
  m.frame_counter = 999999;
  m.trigger_sequence = -1;
  m.width = width;
  m.height = height;
  m.stride = width;
  m.pixel_format = image_t::PIXEL_MONO8;
  m.time_quality = image_t::TIME_SIMULATED;
  m.size = width * height;
  m.data.assign(static_cast<size_t>(m.size), 128);
  return m;
}

vo_delta_t delta(int64_t utime, double dx) {
  vo_delta_t m{};
  m.utime = utime;
  m.prev_utime = utime - 71429;
  m.dx = dx;
  for (int i = 0; i < 6; ++i) m.covariance[i][i] = 0.01;
  m.altitude_m = 200.0;
  m.inliers = 300;
  m.variant = "paper";
  return m;
}

// Offsets of length fields (after the 8-byte fingerprint): image_t.size
// follows 4 int64, 3 int32, 2 int8, 2 float; tracks_t.num_tracks follows
// 3 int64 and 3 int32.
constexpr size_t kImageSizeOffset = 8 + 32 + 12 + 2 + 8;
constexpr size_t kTracksCountOffset = 8 + 24 + 12;

}  // namespace

const std::vector<std::string>& hostile_kinds() {
  static const std::vector<std::string> kinds = {
      "random_bytes",          "truncated_ins",        "ins_nan_attitude",    "ins_infinite_attitude",
      "ins_1e9_rad_attitude",  "ins_10s_ahead",        "altimeter_nan_range", "altimeter_zero_range",
      "altimeter_negative",    "altimeter_20s_behind", "tracks_nan",          "tracks_1e30",
      "tracks_10s_behind",     "image_0x0",            "image_size_mismatch", "image_size_negative",
      "image_size_huge",       "tracks_count_negative", "tracks_count_huge",  "image_10s_ahead",
      "vo_delta_1km_step",     "vo_delta_10s_ahead",   "vo_delta_nan_covariance", "status_counters_negative",
      "config_empty_string",   "tracks_10s_ahead",     "altimeter_10s_ahead",
  };
  return kinds;
}

HostileMessage hostile_message(size_t index, int64_t now_us, int width, int height, std::mt19937_64& rng) {
  const std::vector<std::string>& kinds = hostile_kinds();
  HostileMessage m;
  m.kind = kinds[index % kinds.size()];
  const std::string& k = m.kind;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  if (k == "random_bytes") {
    static const char* const channels[] = {channels::kIns, channels::kAltimeter, channels::kTracks,
                                           channels::kVoDelta, channels::kCameraImage};
    m.channel = channels[rng() % 5];
    m.bytes.resize(8 + rng() % 400);
    for (uint8_t& b : m.bytes) b = static_cast<uint8_t>(rng());
  } else if (k == "truncated_ins") {
    m.channel = channels::kIns;
    m.bytes = encode(ins(now_us, 0.0));
    m.bytes.resize(1 + rng() % (m.bytes.size() - 1));
  } else if (k.rfind("ins_", 0) == 0) {
    m.channel = channels::kIns;
    const double value = k == "ins_nan_attitude" ? nan : k == "ins_infinite_attitude" ? INFINITY
                                                   : k == "ins_1e9_rad_attitude"    ? 1e9
                                                                                    : 0.0;
    m.bytes = encode(ins(k == "ins_10s_ahead" ? now_us + 10 * kSecond : now_us, value));
  } else if (k.rfind("altimeter_", 0) == 0) {
    m.channel = channels::kAltimeter;
    const double range = k == "altimeter_nan_range" ? nan : k == "altimeter_zero_range" ? 0.0
                                                        : k == "altimeter_negative"     ? -50.0
                                                                                        : 123.0;
    const int64_t t = k == "altimeter_20s_behind" ? now_us - 20 * kSecond
                      : k == "altimeter_10s_ahead" ? now_us + 10 * kSecond
                                                   : now_us;
    m.bytes = encode(altimeter(t, range));
  } else if (k == "tracks_count_negative" || k == "tracks_count_huge") {
    m.channel = channels::kTracks;
    m.bytes = encode(tracks(now_us, 1.0, 2));
    put_i32(&m.bytes, kTracksCountOffset, k == "tracks_count_negative" ? -1 : std::numeric_limits<int32_t>::max());
  } else if (k.rfind("tracks_", 0) == 0) {
    m.channel = channels::kTracks;
    const double value = k == "tracks_nan" ? nan : k == "tracks_1e30" ? 1e30 : 0.1;
    const int64_t t = k == "tracks_10s_behind" ? now_us - 10 * kSecond
                      : k == "tracks_10s_ahead" ? now_us + 10 * kSecond
                                                : now_us;
    m.bytes = encode(tracks(t, value));
  } else if (k == "image_size_negative" || k == "image_size_huge") {
    m.channel = channels::kCameraImage;
    m.bytes = encode(image(now_us, 4, 4));
    put_i32(&m.bytes, kImageSizeOffset, k == "image_size_negative" ? -1 : std::numeric_limits<int32_t>::max());
  } else if (k.rfind("image_", 0) == 0) {
    m.channel = channels::kCameraImage;
    if (k == "image_0x0") {
      m.bytes = encode(image(now_us, 0, 0));
    } else if (k == "image_size_mismatch") {
      image_t bad = image(now_us, width, height);
      bad.size = 1000;
      bad.data.resize(1000);
      m.bytes = encode(bad);
    } else {
      m.bytes = encode(image(now_us + 10 * kSecond, width, height));
    }
  } else if (k.rfind("vo_delta_", 0) == 0) {
    m.channel = channels::kVoDelta;
    vo_delta_t d = delta(k == "vo_delta_10s_ahead" ? now_us + 10 * kSecond : now_us,
                         k == "vo_delta_1km_step" ? 1000.0 : 1.5);
    if (k == "vo_delta_nan_covariance") d.covariance[0][0] = nan;
    m.bytes = encode(d);
  } else if (k == "status_counters_negative") {
    m.channel = channels::kStatus;
    status_t s{};
    s.utime = now_us;
    s.name = "hostile";
    m.bytes = encode(s);
    put_i32(&m.bytes, m.bytes.size() - 4, -1);
  } else {
    m.channel = channels::kConfig;
    config_t c{};
    c.name = "hostile";
    m.bytes = encode(c);
    put_i32(&m.bytes, 16, 0);  // config_t.name's length: 0 (an LCM string has at least its terminator)
  }
  return m;
}

}  // namespace nadir
