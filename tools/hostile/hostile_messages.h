#pragma once
// Messages a misconfigured driver, a second simulator on the same network or
// an attacker could put on nadir's channels: undecodable bytes, negative and
// huge length fields, values no sensor can produce, and valid messages stamped
// far in the past or the future. Each is built for a given sensor time "now"
// so that, sent during a live run, it lands among the real messages.

#include <cstdint>
#include <random>
#include <string>
#include <vector>

namespace nadir {

struct HostileMessage {
  std::string kind;      // e.g. "ins_nan_attitude", names the case in counts
  std::string channel;
  std::vector<uint8_t> bytes;
};

// The cases, in the order hostile_message() cycles through them.
const std::vector<std::string>& hostile_kinds();

// Case `index % hostile_kinds().size()` at sensor time `now_us`; `rng` draws
// random bytes and cut points. Image cases use `width` x `height` frames.
HostileMessage hostile_message(size_t index, int64_t now_us, int width, int height, std::mt19937_64& rng);

}  // namespace nadir
