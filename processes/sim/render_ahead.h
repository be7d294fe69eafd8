#pragma once
// Live mode renders ahead of the clock: a producer thread runs the simulator
// (rendering a frame takes ~30 ms) into a bounded queue while the publisher
// sends each message at its due time. Without it every image would leave one
// render time after its trigger -- latency a real camera does not have.

#include <condition_variable>
#include <cstddef>
#include <deque>
#include <mutex>
#include <thread>

#include "processes/sim/simulator.h"

namespace nadir::sim {

class RenderAhead {
 public:
  // Starts producing at once; `capacity` events are kept ready (~1 s of flight
  // at 256). The producer thread runs at `niceness` (0..19, lower priority
  // than the publisher and than the estimator processes fed by it: the
  // renderer stands in for a camera, which takes no CPU from them).
  RenderAhead(Simulator& sim, size_t capacity, int niceness = 0);
  ~RenderAhead();
  RenderAhead(const RenderAhead&) = delete;
  RenderAhead& operator=(const RenderAhead&) = delete;

  // Next event in order; false when the flight is over or stop() was called.
  bool pop(SimEvent* event);
  // Stops the producer and waits for it; the simulator is free afterwards.
  void stop();
  // Simulator counts and time as of the newest event handed out by pop().
  SimulatorCounts counts() const;
  double sim_time_s() const;

 private:
  struct Item {
    SimEvent event;
    SimulatorCounts counts;
    double sim_time_s;
  };
  void produce();
  int niceness_;

  Simulator& sim_;
  size_t capacity_;
  mutable std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<Item> queue_;
  bool finished_ = false;
  bool stopping_ = false;
  SimulatorCounts popped_counts_{};
  double popped_sim_time_s_ = 0.0;
  std::thread producer_;
};

}  // namespace nadir::sim
