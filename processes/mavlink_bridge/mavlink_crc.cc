#include "processes/mavlink_bridge/mavlink_crc.h"

namespace nadir::mavlink {

uint16_t crc_accumulate(uint8_t byte, uint16_t crc) {
  // The MAVLink reference implementation (checksum.h), bit for bit.
  uint8_t tmp = static_cast<uint8_t>(byte ^ static_cast<uint8_t>(crc & 0xFF));
  tmp = static_cast<uint8_t>(tmp ^ static_cast<uint8_t>(tmp << 4));
  return static_cast<uint16_t>((crc >> 8) ^ (tmp << 8) ^ (tmp << 3) ^ (tmp >> 4));
}

uint16_t crc_accumulate(const uint8_t* data, size_t size, uint16_t crc) {
  for (size_t i = 0; i < size; ++i) crc = crc_accumulate(data[i], crc);
  return crc;
}

}  // namespace nadir::mavlink
