// How long a process spends on one message before it can take the next:
// valid messages of full size against hostile ones that declare huge or
// negative lengths. The guard must decide a hostile message in about the time
// it takes to read its header ("no stall over 10 ms").
#include <benchmark/benchmark.h>

#include <climits>
#include <vector>

#include "common/channels.h"
#include "common/lcm_bus.h"
#include "common/message_guard.h"
#include "nadir/image_t.hpp"
#include "nadir/tracks_t.hpp"

namespace nadir {
namespace {

image_t full_image() {
  image_t m{};
  m.width = 612;
  m.height = 512;
  m.stride = 612;
  m.pixel_format = image_t::PIXEL_MONO8;
  m.size = 612 * 512;
  m.data.assign(static_cast<size_t>(m.size), 9);
  return m;
}

tracks_t full_tracks(int n) {
  tracks_t m{};
  m.num_tracks = n;
  m.track_id.assign(n, 1);
  m.age.assign(n, 2);
  m.prev_px.assign(n, std::vector<float>{1.0f, 2.0f});
  m.curr_px.assign(n, std::vector<float>{1.5f, 2.5f});
  m.prev_norm.assign(n, std::vector<double>{0.1, 0.2});
  m.curr_norm.assign(n, std::vector<double>{0.15, 0.25});
  return m;
}

// An empty message of the type with its (only) length field overwritten:
// the bytes of a header that declares `length` elements and carries none.
template <class Msg>
std::vector<uint8_t> declaring(Msg empty, int32_t length) {
  std::vector<uint8_t> bytes = encode_message(empty);
  const uint32_t u = static_cast<uint32_t>(length);
  const size_t at = bytes.size() - 4;  // the count is the last field before the (empty) arrays
  for (int i = 0; i < 4; ++i) bytes[at + i] = static_cast<uint8_t>(u >> (24 - 8 * i));
  return bytes;
}

template <class Msg>
void decide(benchmark::State& state, const std::vector<uint8_t>& bytes, bool expect_ok) {
  for (auto _ : state) {
    Msg msg;
    std::string reason;
    const bool ok = decode_message(bytes.data(), bytes.size(), &msg, &reason);
    if (ok != expect_ok) state.SkipWithError("unexpected decision");
    benchmark::DoNotOptimize(msg);
  }
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations() * bytes.size()));
}

void BM_ValidImage612x512(benchmark::State& s) { decide<image_t>(s, encode_message(full_image()), true); }
void BM_ImageDeclaring2e31(benchmark::State& s) { decide<image_t>(s, declaring(image_t{}, INT32_MAX), false); }
void BM_ImageDeclaringMinus1(benchmark::State& s) { decide<image_t>(s, declaring(image_t{}, -1), false); }
void BM_ValidTracks300(benchmark::State& s) { decide<tracks_t>(s, encode_message(full_tracks(300)), true); }
void BM_TracksDeclaring2e31(benchmark::State& s) { decide<tracks_t>(s, declaring(tracks_t{}, INT32_MAX), false); }
void BM_TracksDeclaringMinus1(benchmark::State& s) { decide<tracks_t>(s, declaring(tracks_t{}, -1), false); }

// The whole receive path of a live process: LCM (memq), the guard, the
// malformed count. One hostile image per iteration.
void BM_BusHostileImage(benchmark::State& state) {
  LcmBusOptions options;
  options.url = "memq://";
  LcmBus bus(options);
  int64_t delivered = 0;
  bus.subscribe<image_t>(channels::kCameraImage, [&](const image_t&) { ++delivered; });
  const std::vector<uint8_t> bytes = declaring(image_t{}, INT32_MAX);
  for (auto _ : state) {
    bus.publish_raw(channels::kCameraImage, bytes.data(), bytes.size());
    bus.handle(0);
  }
  if (delivered != 0 || bus.error_counts().malformed != static_cast<int64_t>(state.iterations())) {
    state.SkipWithError("hostile image delivered or not counted");
  }
}

BENCHMARK(BM_ValidImage612x512);
BENCHMARK(BM_ImageDeclaring2e31);
BENCHMARK(BM_ImageDeclaringMinus1);
BENCHMARK(BM_ValidTracks300);
BENCHMARK(BM_TracksDeclaring2e31);
BENCHMARK(BM_TracksDeclaringMinus1);
BENCHMARK(BM_BusHostileImage);

}  // namespace
}  // namespace nadir
