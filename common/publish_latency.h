#pragma once
// Sensor time -> publish latency of one published message, for STATUS.

#include <cstddef>
#include <cstdint>
#include <string>

#include "common/status.h"

namespace nadir {

// Adds now - utime of an encoded message to `window`; STATUS and CONFIG
// (bookkeeping, stamped when sent) and undecodable buffers are skipped.
void note_publish_latency(const std::string& channel, const uint8_t* data, size_t size, LatencyWindow* window);

}  // namespace nadir
