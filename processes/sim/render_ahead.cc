#include "processes/sim/render_ahead.h"

#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <cstdio>

namespace nadir::sim {

RenderAhead::RenderAhead(Simulator& sim, size_t capacity, int niceness)
    : niceness_(niceness), sim_(sim), capacity_(capacity < 1 ? 1 : capacity), producer_([this] { produce(); }) {}

RenderAhead::~RenderAhead() { stop(); }

void RenderAhead::produce() {
  // Linux: niceness is per thread (PRIO_PROCESS with the thread id).
  if (niceness_ > 0 && setpriority(PRIO_PROCESS, static_cast<id_t>(syscall(SYS_gettid)), niceness_) != 0) {
    std::perror("nadir_sim: render thread niceness not set");
  }
  for (;;) {
    Item item;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      changed_.wait(lock, [this] { return stopping_ || queue_.size() < capacity_; });
      if (stopping_) break;
    }
    // The simulator is only ever touched by this thread.
    if (!sim_.next(&item.event)) break;
    item.counts = sim_.counts();
    item.sim_time_s = sim_.sim_time_s();
    std::lock_guard<std::mutex> lock(mutex_);
    queue_.push_back(std::move(item));
    changed_.notify_all();
  }
  std::lock_guard<std::mutex> lock(mutex_);
  finished_ = true;
  changed_.notify_all();
}

bool RenderAhead::pop(SimEvent* event) {
  std::unique_lock<std::mutex> lock(mutex_);
  changed_.wait(lock, [this] { return stopping_ || finished_ || !queue_.empty(); });
  if (stopping_ || queue_.empty()) return false;
  Item& item = queue_.front();
  *event = std::move(item.event);
  popped_counts_ = item.counts;
  popped_sim_time_s_ = item.sim_time_s;
  queue_.pop_front();
  changed_.notify_all();
  return true;
}

void RenderAhead::stop() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
    changed_.notify_all();
  }
  if (producer_.joinable()) producer_.join();
}

SimulatorCounts RenderAhead::counts() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return popped_counts_;
}

double RenderAhead::sim_time_s() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return popped_sim_time_s_;
}

}  // namespace nadir::sim
