#pragma once
// NovAtel's 32-bit CRC (OEM manuals: reflected polynomial 0xEDB88320, initial
// value 0, no final inversion). ASCII logs carry it over the bytes between the
// '#'/'%' and the '*'; binary logs over header + body.

#include <cstddef>
#include <cstdint>

namespace nadir::ins_bridge {

uint32_t novatel_crc32(const uint8_t* data, size_t size, uint32_t crc = 0);

}  // namespace nadir::ins_bridge
