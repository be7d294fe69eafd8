#pragma once
// Bus over a real LCM instance: udpm live (TTL 0 by default), memq:// in tests.

#include <lcm/lcm-cpp.hpp>

#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "common/bus.h"
#include "common/status.h"

namespace nadir {

// Default live URL: multicast on the host only (TTL 0). LCM_DEFAULT_URL wins.
std::string default_lcm_url();

// The UDP port an LCM URL receives on: udpm://ADDRESS:PORT (LCM's 7667
// when the port is left out); 0 for a provider without a socket (memq://,
// file://).
int lcm_receive_port(const std::string& url);

struct LcmBusOptions {
  std::string url;                 // empty: default_lcm_url()
  int queue_capacity = 100;        // per subscription
  int image_queue_capacity = 200;  // for CAMERA_IMAGE: bursts must not drop
  void Check() const;
};

class LcmBus : public Bus {
 public:
  // Throws std::runtime_error naming the URL when LCM cannot start.
  explicit LcmBus(const LcmBusOptions& options);
  ~LcmBus() override;

  void publish_raw(const std::string& channel, const uint8_t* data, size_t size) override;
  void subscribe_raw(const std::string& channel, RawHandler handler) override;

  // Dispatches incoming messages for up to timeout_ms. Returns <0 on error.
  int handle(int timeout_ms);
  int fileno() { return lcm_.getFileno(); }

  // Sensor time -> publish latency of everything published (not STATUS/CONFIG).
  LatencyWindow& latency() { return latency_; }
  // Adds the counters "tx.<CHANNEL>" / "rx.<CHANNEL>" (messages published /
  // delivered since start, STATUS and CONFIG excepted) and "udp_rx_drops"
  // (datagrams the kernel dropped for a full receive buffer of this bus's
  // socket; not of the process's other UDP sockets) to a STATUS.
  // A capture is checked against the tx counts (nadir_log info, nadir_eval),
  // so a message lost between a publisher and the logger is counted.
  // The counts are this bus's: a STATUS relayed onto another bus carries
  // them relabelled (relabel_relayed_transport_counters below).
  void add_transport_counters(status_t* msg);
  // A live process's STATUS: its report, this bus's malformed counts, this
  // process's pid, vehicle time now, the period's latency (then restarted)
  // and the transport counters above.
  status_t status_message(const std::string& name, const StatusReport& report);
  const std::string& url() const { return url_; }

 private:
  struct Subscription;
  static void dispatch(const lcm::ReceiveBuffer* rbuf, const std::string& channel, Subscription* sub);

  std::string url_;
  int receive_port_;  // lcm_receive_port(url_)
  lcm::LCM lcm_;
  LcmBusOptions options_;
  std::mutex publish_mutex_;
  LatencyWindow latency_;
  std::mutex counts_mutex_;
  std::map<std::string, int64_t> tx_counts_, rx_counts_;
  std::vector<std::unique_ptr<Subscription>> subscriptions_;
};

// A STATUS relayed from another bus onto this one (nadir_sim_mavlink relays
// the simulator's, published on the simulator's own bus): its "tx." and "rx."
// counts are that bus's messages, which a capture of this bus does not hold,
// so they are renamed "origin_bus.tx.<CHANNEL>" / "origin_bus.rx.<CHANNEL>".
// A capture is then checked only against the publishers on its own bus; the
// relay counts what it put on it in its own STATUS.
void relabel_relayed_transport_counters(status_t* msg);

}  // namespace nadir
