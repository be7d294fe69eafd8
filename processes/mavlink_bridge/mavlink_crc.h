#pragma once
// The MAVLink checksum: CRC-16/MCRF4XX ("X.25" in the MAVLink sources), seed
// 0xFFFF, over the frame after the start byte, then the message's CRC_EXTRA.

#include <cstddef>
#include <cstdint>
#include <string>

namespace nadir::mavlink {

inline constexpr uint16_t kCrcSeed = 0xFFFF;

uint16_t crc_accumulate(uint8_t byte, uint16_t crc);
uint16_t crc_accumulate(const uint8_t* data, size_t size, uint16_t crc);
inline uint16_t crc_accumulate(const std::string& text, uint16_t crc) {
  return crc_accumulate(reinterpret_cast<const uint8_t*>(text.data()), text.size(), crc);
}

}  // namespace nadir::mavlink
