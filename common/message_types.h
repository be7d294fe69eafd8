#pragma once
// Names the nadir type of an encoded message from its 8-byte fingerprint.

#include <cstddef>
#include <cstdint>
#include <string>

namespace nadir {

// "nadir.image_t", or "unknown (fingerprint 0x...)".
std::string message_type_name(const uint8_t* data, size_t size);

}  // namespace nadir
