#pragma once
// Sentence generation for the parser tests, written independently of the
// bridge's encoder: a bitwise CRC-32 and hand-built field lists, so a test can
// put any field at any value (or break the framing) with a correct CRC.

#include <cstdint>
#include <string>
#include <vector>

namespace nadir::ins_bridge::testing {

// Bit-at-a-time NovAtel CRC-32 (reflected 0xEDB88320, init 0, no final xor).
uint32_t bitwise_crc32(const uint8_t* data, size_t size);

// "<sync><header_fields joined by ','>;<body_fields joined by ','>*<crc>\r\n"
std::string ascii_frame(char sync, const std::vector<std::string>& header, const std::vector<std::string>& body);

std::vector<std::string> long_header(const std::string& name, unsigned week, const std::string& seconds);
std::vector<std::string> short_header(const std::string& name, unsigned week, const std::string& seconds);

// INSPVA body fields: week, seconds, lat, lon, height, vn, ve, vu, roll, pitch, azimuth, status.
struct PvaFields {
  unsigned week = 2300;
  double seconds = 345600.25;
  double lat = 47.3977419, lon = 8.5455938, height = 512.25;
  double vn = 20.5, ve = -3.25, vu = 1.125;
  double roll = 2.5, pitch = -1.75, azimuth = 93.5;
  std::string status = "INS_SOLUTION_GOOD";
  std::vector<std::string> fields() const;
};

std::string inspvaa(const PvaFields& p, unsigned header_week = 0);
std::string inspvasa(const PvaFields& p);

// Binary frame (AA 44 12): header with the given message id and body; the
// length field is body.size() unless length_override >= 0.
std::vector<uint8_t> binary_frame(uint16_t id, unsigned week, uint32_t ms, const std::vector<uint8_t>& body,
                                  int length_override = -1, int header_length_override = -1);
std::vector<uint8_t> inspvab_body(const PvaFields& p, uint32_t status_code = 3);
std::vector<uint8_t> insstdevb_body(const std::vector<float>& sigmas, uint32_t ext_status, uint16_t since_update);

void append(std::vector<uint8_t>* out, const std::string& text);
void append(std::vector<uint8_t>* out, const std::vector<uint8_t>& bytes);

}  // namespace nadir::ins_bridge::testing
