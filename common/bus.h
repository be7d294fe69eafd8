#pragma once
// The only thing a node knows about transport: typed publish and subscribe.
// Implementations: LcmBus (live, any LCM URL) and ReplayBus (lockstep replay).

#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "common/message_guard.h"

namespace nadir {

// Counts of what went wrong while delivering messages on one bus.
struct BusErrorCounts {
  int64_t malformed = 0;       // messages that failed to decode
  int64_t handler_errors = 0;  // handlers that threw
  std::string last_error;      // names the channel and the reason
};

class Bus {
 public:
  using RawHandler = std::function<void(const std::string& channel, const uint8_t* data, size_t size)>;

  virtual ~Bus() = default;

  virtual void publish_raw(const std::string& channel, const uint8_t* data, size_t size) = 0;
  virtual void subscribe_raw(const std::string& channel, RawHandler handler) = 0;
  // Called by a handler that has published everything its subscribers need
  // and goes on with work that publishes nothing (the tracker preparing the
  // next frame): a bus that delivers in-process may hand the messages on now
  // rather than after the handler returns. Order of delivery and of
  // publication is unchanged. LCM delivers at publish time: nothing to do.
  virtual void deliver_pending() {}

  template <class Msg>
  void publish(const std::string& channel, const Msg& msg) {
    const std::vector<uint8_t> buffer = encode_message(msg);
    publish_raw(channel, buffer.data(), buffer.size());
  }

  // The handler sees only messages that decode; others are counted as
  // malformed and reported, never passed on. Declared lengths are checked
  // against the bytes before the decoder allocates anything, and a decoder
  // that throws counts as malformed too. A handler that throws is counted,
  // so one bad message cannot stop a process.
  template <class Msg>
  void subscribe(const std::string& channel, std::function<void(const Msg&)> handler) {
    subscribe_raw(channel, [this, handler](const std::string& ch, const uint8_t* data, size_t size) {
      Msg msg;
      std::string reason;
      if (!decode_message(data, size, &msg, &reason)) {
        note_malformed(ch, size, reason);
        return;
      }
      deliver_guarded(ch, [&] { handler(msg); });
    });
  }

  const BusErrorCounts& error_counts() const { return errors_; }

 protected:
  void note_malformed(const std::string& channel, size_t size, const std::string& reason);
  void deliver_guarded(const std::string& channel, const std::function<void()>& call);

 private:
  BusErrorCounts errors_;
};

// Sensor time (utime, the first field of every nadir type) of an encoded
// message, or nullopt-like false when the buffer is too short.
bool encoded_utime(const uint8_t* data, size_t size, int64_t* utime);

}  // namespace nadir
