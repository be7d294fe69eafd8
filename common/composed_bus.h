#pragma once
// Several nodes live in one process (nadir_composed): what one node publishes
// reaches the others of the process synchronously, in the same thread, with no
// wake-up in between (LocalBus), and also goes out on the outside bus (LCM) so
// that lcm-logger and lcm-spy see every channel as with separate processes.
// Channels no local node produces come in from the outside bus.

#include <memory>
#include <set>
#include <string>

#include "common/bus.h"
#include "common/local_bus.h"
#include "common/status.h"

namespace nadir {

class ComposedBus : public LocalBus {
 public:
  explicit ComposedBus(Bus& outside) : outside_(outside) {}

  // Subscribes the outside bus to every channel a local node listens to that
  // no local node produces; call once, after every node has subscribed.
  // Produced channels are never taken from outside: no message twice.
  void connect_inputs(const std::set<std::string>& produced_locally);

 protected:
  void forward(const std::string& channel, const uint8_t* data, size_t size) override;

 private:
  Bus& outside_;
};

// One node's view of a shared bus: its own decode/handler error counts and
// publish latencies, so each node of a composed process reports its own STATUS.
class NodePort : public Bus {
 public:
  explicit NodePort(Bus& shared) : shared_(shared) {}

  void publish_raw(const std::string& channel, const uint8_t* data, size_t size) override;
  void subscribe_raw(const std::string& channel, RawHandler handler) override;
  void deliver_pending() override { shared_.deliver_pending(); }
  LatencyWindow& latency() { return latency_; }

 private:
  Bus& shared_;
  LatencyWindow latency_;
};

}  // namespace nadir
