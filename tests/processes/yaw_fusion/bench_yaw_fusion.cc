// Per-delta cost of yaw fusion: the filter step alone and a whole frame
// through the estimator (one VO_DELTA with ~7 INS and ~1.4 altimeter samples).

#include <benchmark/benchmark.h>

#include "common/channels.h"
#include "processes/yaw_fusion/pose_filter.h"
#include "processes/yaw_fusion/yaw_fusion_estimator.h"
#include "synthetic_flight.h"

namespace {

void BM_PoseFilterDeltaAndYawUpdate(benchmark::State& state) {
  nadir::PoseFilter filter;
  filter.initialise(0.3, 1e-4);
  const Eigen::Matrix4d cov = Eigen::Matrix4d::Identity() * 1e-3;
  for (auto _ : state) {
    filter.predict_with_delta({2.1, 0.05, -0.07}, 0.001, cov);
    benchmark::DoNotOptimize(filter.update_yaw(0.3, 1e-4, 3.0));
  }
}
BENCHMARK(BM_PoseFilterDeltaAndYawUpdate);

void BM_EstimatorPerFrame(benchmark::State& state) {
  nadir::test::FlightSpec spec;
  spec.frames = 2000;
  spec.ins_yaw_stddev_deg = 0.3;
  spec.dyaw_stddev_deg = 0.05;
  const auto flight = nadir::test::make_flight(spec);
  std::vector<nadir::vo_delta_t> deltas = flight.deltas;
  for (auto _ : state) {
    state.PauseTiming();
    nadir::YawFusionEstimator estimator{nadir::YawFusionOptions{}};
    size_t ins = 0, alt = 0;
    state.ResumeTiming();
    for (const auto& d : deltas) {
      while (ins < flight.ins.size() && flight.ins[ins].utime <= d.utime) estimator.add_ins(flight.ins[ins++]);
      while (alt < flight.altimeter.size() && flight.altimeter[alt].utime <= d.utime) {
        estimator.add_altimeter(flight.altimeter[alt++]);
      }
      benchmark::DoNotOptimize(estimator.add_vo_delta(d));
    }
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(deltas.size()));
}
BENCHMARK(BM_EstimatorPerFrame)->Unit(benchmark::kMillisecond);

}  // namespace
