#include "common/composed_bus.h"

#include "common/publish_latency.h"

namespace nadir {

void ComposedBus::connect_inputs(const std::set<std::string>& produced_locally) {
  for (const std::string& channel : subscribed_channels()) {
    if (produced_locally.count(channel) != 0) continue;
    outside_.subscribe_raw(channel, [this](const std::string& ch, const uint8_t* data, size_t size) {
      deliver(ch, data, size);
    });
  }
}

void ComposedBus::forward(const std::string& channel, const uint8_t* data, size_t size) {
  outside_.publish_raw(channel, data, size);
}

void NodePort::publish_raw(const std::string& channel, const uint8_t* data, size_t size) {
  note_publish_latency(channel, data, size, &latency_);
  shared_.publish_raw(channel, data, size);
}

void NodePort::subscribe_raw(const std::string& channel, RawHandler handler) {
  shared_.subscribe_raw(channel, std::move(handler));
}

}  // namespace nadir
