#pragma once
// A trigger source fed by code: tests script edge sequences (missing, double,
// spurious edges) and the fake-camera integration tests emit one edge per
// software trigger. Thread-safe: emit() from one thread, poll() from another.

#include <condition_variable>
#include <deque>
#include <mutex>

#include "processes/camera_capture/trigger_source.h"

namespace nadir {

class ScriptedTriggerSource : public TriggerSource {
 public:
  // Queues an edge at the given vehicle time (device time = the same value)
  // and returns it with its sequence number.
  TriggerEdge emit(int64_t vehicle_us, int8_t edge = 1);
  // Queues a fully specified edge (sequence and device time as given).
  void push(const TriggerEdge& edge);

  void poll(int timeout_ms, std::vector<TriggerEdge>* edges) override;
  std::string describe() const override { return "scripted"; }

 private:
  std::mutex mutex_;
  std::condition_variable ready_;
  std::deque<TriggerEdge> queue_;
  int64_t next_sequence_ = 0;
};

}  // namespace nadir
