#pragma once
// In-process delivery of what nodes publish to the other nodes of the same
// process, synchronously and in FIFO order after the handler that published
// returns (or when it calls deliver_pending()). Shared by lockstep replay (ReplayBus: everything also goes to the
// output log) and composed live processes (ComposedBus: everything also goes
// out on LCM).

#include <cstdint>
#include <deque>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "common/bus.h"

namespace nadir {

class LocalBus : public Bus {
 public:
  // Hands the message to forward(), then queues it for local subscribers.
  void publish_raw(const std::string& channel, const uint8_t* data, size_t size) final;
  void subscribe_raw(const std::string& channel, RawHandler handler) override;

  // Delivers one message to its subscribers, then everything published in
  // response, until nothing is pending.
  void deliver(const std::string& channel, const uint8_t* data, size_t size);
  // Drains the queue now unless an outer deliver() is already draining it.
  void deliver_pending() final;
  // Channels with at least one local subscriber.
  std::vector<std::string> subscribed_channels() const;

 protected:
  // Where every published message goes besides the local subscribers.
  virtual void forward(const std::string& channel, const uint8_t* data, size_t size) = 0;

 private:
  void dispatch(const std::string& channel, const uint8_t* data, size_t size);
  void drain();

  std::map<std::string, std::vector<RawHandler>> handlers_;
  std::deque<std::pair<std::string, std::vector<uint8_t>>> pending_;
  bool draining_ = false;
};

}  // namespace nadir
