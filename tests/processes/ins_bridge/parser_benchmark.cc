// Throughput of the NovAtel framer/decoder and the altimeter line path
// (timings live here, never in tests). Run: build/bin/nadir_bench_ins_bridge_parsers

#include <benchmark/benchmark.h>

#include "processes/ins_bridge/altimeter_parser.h"
#include "processes/ins_bridge/line_splitter.h"
#include "processes/ins_bridge/novatel_parser.h"
#include "tests/processes/ins_bridge/test_sentences.h"

namespace nadir::ins_bridge {
namespace {

std::vector<uint8_t> stream(bool binary) {
  std::vector<uint8_t> s;
  for (int i = 0; i < 100; ++i) {
    testing::PvaFields p;
    p.seconds = 1000 + i * 0.01;
    if (binary) testing::append(&s, testing::binary_frame(kInspvaId, p.week, 1000000, testing::inspvab_body(p)));
    else testing::append(&s, testing::inspvaa(p));
  }
  return s;
}

void parse(benchmark::State& state, bool binary) {
  const std::vector<uint8_t> bytes = stream(binary);
  NovatelParser parser;
  std::vector<NovatelFrame> frames;
  for (auto _ : state) {
    frames.clear();
    parser.feed(bytes.data(), bytes.size(), 0, 20.0, &frames);
    benchmark::DoNotOptimize(frames.data());
  }
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations() * bytes.size()));
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * 100));
}
void BM_InspvaaAscii(benchmark::State& state) { parse(state, false); }
void BM_InspvabBinary(benchmark::State& state) { parse(state, true); }
BENCHMARK(BM_InspvaaAscii);
BENCHMARK(BM_InspvabBinary);

void BM_AltimeterLines(benchmark::State& state) {
  std::vector<uint8_t> bytes;
  for (int i = 0; i < 100; ++i) testing::append(&bytes, "123.45 m 87%\r\n");
  LineSplitter splitter;
  const LightwareAsciiParser parser;
  std::vector<SerialLine> lines;
  for (auto _ : state) {
    lines.clear();
    splitter.feed(bytes.data(), bytes.size(), 0, 87.0, &lines);
    for (const SerialLine& line : lines) benchmark::DoNotOptimize(parser.parse(line.text).range_m);
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * 100));
}
BENCHMARK(BM_AltimeterLines);

}  // namespace
}  // namespace nadir::ins_bridge
