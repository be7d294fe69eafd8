// Per-frame cost from a filled Aravis buffer to a published LCM message: the
// one copy into the encoded image_t (header encode + memcpy), and the same
// through Bus::publish over memq (what nadir_camera_capture does per frame).

#include <arv.h>
#include <benchmark/benchmark.h>

#include <cstring>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "common/channels.h"
#include "common/lcm_bus.h"
#include "processes/camera_capture/image_message.h"

namespace nadir {
namespace {

constexpr int kWidth = 612;
constexpr int kHeight = 512;

image_t header() {
  image_t h{};
  h.utime = 1'700'000'000'000'000;
  h.width = kWidth;
  h.height = kHeight;
  h.stride = kWidth;
  h.pixel_format = image_t::PIXEL_MONO8;
  h.time_quality = image_t::TIME_TRIGGER;
  return h;
}

void BM_EncodeOneCopy(benchmark::State& state) {
  ArvBuffer* buffer = arv_buffer_new_allocate(static_cast<size_t>(kWidth) * kHeight);
  // A fresh buffer reports a received size of 0: use the allocation size.
  const size_t size = static_cast<size_t>(kWidth) * kHeight;
  void* pixels = const_cast<void*>(arv_buffer_get_data(buffer, nullptr));
  std::memset(pixels, 7, size);
  ImageMessageEncoder encoder;
  const image_t h = header();
  for (auto _ : state) {
    std::memcpy(encoder.begin(h, size), pixels, size);
    benchmark::DoNotOptimize(encoder.data());
  }
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations()) * static_cast<int64_t>(size));
  g_object_unref(buffer);
}
BENCHMARK(BM_EncodeOneCopy);

// For comparison: the generic path (copy into image_t.data, then encode).
void BM_EncodeGeneratedTwoCopies(benchmark::State& state) {
  std::vector<uint8_t> pixels(static_cast<size_t>(kWidth) * kHeight, 7);
  image_t msg = header();
  std::vector<uint8_t> out;
  for (auto _ : state) {
    msg.data.assign(pixels.begin(), pixels.end());
    msg.size = static_cast<int32_t>(msg.data.size());
    out.resize(static_cast<size_t>(msg.getEncodedSize()));
    msg.encode(out.data(), 0, static_cast<int>(out.size()));
    benchmark::DoNotOptimize(out.data());
  }
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations()) * static_cast<int64_t>(pixels.size()));
}
BENCHMARK(BM_EncodeGeneratedTwoCopies);

void BM_BufferToPublishedMemq(benchmark::State& state) {
  ArvBuffer* buffer = arv_buffer_new_allocate(static_cast<size_t>(kWidth) * kHeight);
  // A fresh buffer reports a received size of 0: use the allocation size.
  const size_t size = static_cast<size_t>(kWidth) * kHeight;
  void* pixels = const_cast<void*>(arv_buffer_get_data(buffer, nullptr));
  std::memset(pixels, 7, size);
  LcmBusOptions options;
  options.url = "memq://";
  LcmBus bus(options);
  int64_t delivered = 0;
  bus.subscribe_raw(channels::kCameraImage, [&](const std::string&, const uint8_t*, size_t) { ++delivered; });
  ImageMessageEncoder encoder;
  image_t h = header();
  for (auto _ : state) {
    ++h.frame_counter;
    std::memcpy(encoder.begin(h, size), pixels, size);
    bus.publish_raw(channels::kCameraImage, encoder.data(), encoder.size());
    bus.handle(0);  // drain memq so it does not grow
  }
  state.counters["delivered"] = static_cast<double>(delivered);
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations()) * static_cast<int64_t>(size));
  g_object_unref(buffer);
}
BENCHMARK(BM_BufferToPublishedMemq);

// Bayer sensors: the conversion to mono writes straight into the message.
void BM_BayerToMonoIntoMessage(benchmark::State& state) {
  std::vector<uint8_t> raw(static_cast<size_t>(kWidth) * kHeight, 90);
  ImageMessageEncoder encoder;
  const image_t h = header();
  for (auto _ : state) {
    uint8_t* out = encoder.begin(h, raw.size());
    const cv::Mat bayer(kHeight, kWidth, CV_8UC1, raw.data());
    cv::Mat gray(kHeight, kWidth, CV_8UC1, out);
    cv::cvtColor(bayer, gray, cv::COLOR_BayerBG2GRAY);
    benchmark::DoNotOptimize(encoder.data());
  }
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations()) * static_cast<int64_t>(raw.size()));
}
BENCHMARK(BM_BayerToMonoIntoMessage);

}  // namespace
}  // namespace nadir
