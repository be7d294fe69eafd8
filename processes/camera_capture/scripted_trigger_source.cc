#include "processes/camera_capture/scripted_trigger_source.h"

#include <chrono>

namespace nadir {

TriggerEdge ScriptedTriggerSource::emit(int64_t vehicle_us, int8_t edge) {
  TriggerEdge e;
  e.device_us = vehicle_us;
  e.vehicle_us = vehicle_us;
  e.edge = edge;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    e.sequence = next_sequence_++;
    queue_.push_back(e);
  }
  ready_.notify_all();
  return e;
}

void ScriptedTriggerSource::push(const TriggerEdge& edge) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    queue_.push_back(edge);
    next_sequence_ = edge.sequence + 1;
  }
  ready_.notify_all();
}

void ScriptedTriggerSource::poll(int timeout_ms, std::vector<TriggerEdge>* edges) {
  std::unique_lock<std::mutex> lock(mutex_);
  if (queue_.empty() && timeout_ms > 0) {
    ready_.wait_for(lock, std::chrono::milliseconds(timeout_ms), [this] { return !queue_.empty(); });
  }
  while (!queue_.empty()) {
    edges->push_back(queue_.front());
    queue_.pop_front();
  }
}

}  // namespace nadir
