#include "common/lcm_bus.h"

#include <unistd.h>

#include <cstdlib>
#include <stdexcept>

#include "common/channels.h"
#include "common/config.h"
#include "common/publish_latency.h"
#include "common/time_base.h"
#include "common/udp_drops.h"

namespace nadir {

std::string default_lcm_url() {
  const char* env = std::getenv("LCM_DEFAULT_URL");
  if (env != nullptr && *env != '\0') return env;
  // TTL 0: nothing leaves the host. A 4 MB kernel receive buffer holds a
  // burst of full-size images (lcm-logger loses most of them without it).
  return "udpm://239.255.76.67:7667?ttl=0&recv_buf_size=4194304";
}

int lcm_receive_port(const std::string& url) {
  const std::string scheme = "udpm://";
  if (url.rfind(scheme, 0) != 0) return 0;
  const std::string address = url.substr(scheme.size(), url.find('?') - scheme.size());
  const size_t colon = address.rfind(':');
  if (colon == std::string::npos || colon + 1 == address.size()) return 7667;  // LCM's default port
  try {
    return std::stoi(address.substr(colon + 1));
  } catch (const std::exception&) {
    return 0;  // LCM refuses such a URL itself
  }
}

void LcmBusOptions::Check() const {
  require_option(queue_capacity >= 1 && queue_capacity <= 100000, "lcm", "queue_capacity", "must be in [1, 100000]");
  require_option(image_queue_capacity >= 1 && image_queue_capacity <= 100000, "lcm", "image_queue_capacity",
                 "must be in [1, 100000]");
}

struct LcmBus::Subscription {
  LcmBus* bus;
  RawHandler handler;
};

LcmBus::LcmBus(const LcmBusOptions& options)
    : url_(options.url.empty() ? default_lcm_url() : options.url),
      receive_port_(lcm_receive_port(url_)),
      lcm_(url_),
      options_(options) {
  options_.Check();
  if (!lcm_.good()) throw std::runtime_error("LCM could not start on '" + url_ + "'");
}

LcmBus::~LcmBus() = default;

void LcmBus::publish_raw(const std::string& channel, const uint8_t* data, size_t size) {
  note_publish_latency(channel, data, size, &latency_);
  {
    std::lock_guard<std::mutex> lock(publish_mutex_);
    if (lcm_.publish(channel, data, static_cast<unsigned int>(size)) != 0) {
      throw std::runtime_error("LCM publish on " + channel + " failed (" + url_ + ")");
    }
  }
  // Counted once sent: a STATUS built afterwards (on any thread) leaves the
  // same socket after this message, so a capture holds it before that STATUS.
  if (!channels::is_bookkeeping(channel)) {
    std::lock_guard<std::mutex> lock(counts_mutex_);
    ++tx_counts_[channel];
  }
}

void LcmBus::dispatch(const lcm::ReceiveBuffer* rbuf, const std::string& channel, Subscription* sub) {
  if (!channels::is_bookkeeping(channel)) {
    std::lock_guard<std::mutex> lock(sub->bus->counts_mutex_);
    ++sub->bus->rx_counts_[channel];
  }
  sub->handler(channel, static_cast<const uint8_t*>(rbuf->data), rbuf->data_size);
}

status_t LcmBus::status_message(const std::string& name, const StatusReport& report) {
  status_t msg = make_status_message(name, static_cast<int32_t>(getpid()), vehicle_time_now_us(), report, error_counts());
  latency_.take(&msg.latency_p50_ms, &msg.latency_p99_ms, &msg.latency_max_ms);
  add_transport_counters(&msg);
  return msg;
}

void LcmBus::add_transport_counters(status_t* msg) {
  auto add = [msg](const std::string& name, double value) {
    msg->counter_names.push_back(name);
    msg->counter_values.push_back(value);
  };
  {
    std::lock_guard<std::mutex> lock(counts_mutex_);
    for (const auto& [channel, n] : tx_counts_) add("tx." + channel, static_cast<double>(n));
    for (const auto& [channel, n] : rx_counts_) add("rx." + channel, static_cast<double>(n));
  }
  if (receive_port_ > 0) {
    const int64_t drops = own_udp_receive_drops(receive_port_);
    if (drops >= 0) add("udp_rx_drops", static_cast<double>(drops));
  }
  msg->num_counters = static_cast<int32_t>(msg->counter_names.size());
}

void relabel_relayed_transport_counters(status_t* msg) {
  for (std::string& name : msg->counter_names) {
    if (name.rfind("tx.", 0) == 0 || name.rfind("rx.", 0) == 0) name = "origin_bus." + name;
  }
}

void LcmBus::subscribe_raw(const std::string& channel, RawHandler handler) {
  subscriptions_.push_back(std::make_unique<Subscription>(Subscription{this, std::move(handler)}));
  lcm::Subscription* sub = lcm_.subscribeFunction(channel, &LcmBus::dispatch, subscriptions_.back().get());
  if (sub == nullptr) throw std::runtime_error("LCM could not subscribe to " + channel);
  sub->setQueueCapacity(channel == channels::kCameraImage ? options_.image_queue_capacity : options_.queue_capacity);
}

int LcmBus::handle(int timeout_ms) { return lcm_.handleTimeout(timeout_ms); }

}  // namespace nadir
