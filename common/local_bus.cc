#include "common/local_bus.h"

namespace nadir {

void LocalBus::publish_raw(const std::string& channel, const uint8_t* data, size_t size) {
  forward(channel, data, size);
  if (handlers_.count(channel) != 0) pending_.emplace_back(channel, std::vector<uint8_t>(data, data + size));
}

void LocalBus::subscribe_raw(const std::string& channel, RawHandler handler) {
  handlers_[channel].push_back(std::move(handler));
}

std::vector<std::string> LocalBus::subscribed_channels() const {
  std::vector<std::string> out;
  for (const auto& [channel, handlers] : handlers_) out.push_back(channel);
  return out;
}

void LocalBus::dispatch(const std::string& channel, const uint8_t* data, size_t size) {
  const auto it = handlers_.find(channel);
  if (it == handlers_.end()) return;
  for (const RawHandler& handler : it->second) handler(channel, data, size);
}

void LocalBus::deliver(const std::string& channel, const uint8_t* data, size_t size) {
  dispatch(channel, data, size);
  drain();
}

void LocalBus::deliver_pending() { drain(); }

void LocalBus::drain() {
  if (draining_) return;  // an outer call drains
  draining_ = true;
  while (!pending_.empty()) {
    const auto message = std::move(pending_.front());
    pending_.pop_front();
    dispatch(message.first, message.second.data(), message.second.size());
  }
  draining_ = false;
}

}  // namespace nadir
