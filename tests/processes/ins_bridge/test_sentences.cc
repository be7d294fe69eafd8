#include "tests/processes/ins_bridge/test_sentences.h"

#include <cstdio>
#include <cstring>

namespace nadir::ins_bridge::testing {
namespace {

std::string fmt(const char* format, double value) {
  char text[64];
  std::snprintf(text, sizeof text, format, value);
  return text;
}

std::string join(const std::vector<std::string>& fields) {
  std::string out;
  for (size_t i = 0; i < fields.size(); ++i) out += (i ? "," : "") + fields[i];
  return out;
}

void le(std::vector<uint8_t>* out, uint64_t value, int bytes) {
  for (int i = 0; i < bytes; ++i) out->push_back(static_cast<uint8_t>(value >> (8 * i)));
}
void le_double(std::vector<uint8_t>* out, double v) {
  uint64_t bits;
  std::memcpy(&bits, &v, 8);
  le(out, bits, 8);
}
void le_float(std::vector<uint8_t>* out, float v) {
  uint32_t bits;
  std::memcpy(&bits, &v, 4);
  le(out, bits, 4);
}

}  // namespace

uint32_t bitwise_crc32(const uint8_t* data, size_t size) {
  uint32_t crc = 0;
  for (size_t i = 0; i < size; ++i) {
    crc ^= data[i];
    for (int bit = 0; bit < 8; ++bit) crc = (crc >> 1) ^ ((crc & 1u) ? 0xEDB88320u : 0u);
  }
  return crc;
}

std::string ascii_frame(char sync, const std::vector<std::string>& header, const std::vector<std::string>& body) {
  const std::string inner = join(header) + ";" + join(body);
  char crc[16];
  std::snprintf(crc, sizeof crc, "*%08x\r\n",
                bitwise_crc32(reinterpret_cast<const uint8_t*>(inner.data()), inner.size()));
  return std::string(1, sync) + inner + crc;
}

std::vector<std::string> long_header(const std::string& name, unsigned week, const std::string& seconds) {
  return {name, "COM1", "0", "42.5", "FINESTEERING", std::to_string(week), seconds, "02000020", "cdba", "32768"};
}

std::vector<std::string> short_header(const std::string& name, unsigned week, const std::string& seconds) {
  return {name, std::to_string(week), seconds};
}

std::vector<std::string> PvaFields::fields() const {
  return {std::to_string(week),    fmt("%.9f", seconds), fmt("%.11f", lat),     fmt("%.11f", lon),
          fmt("%.4f", height),     fmt("%.4f", vn),      fmt("%.4f", ve),       fmt("%.4f", vu),
          fmt("%.9f", roll),       fmt("%.9f", pitch),   fmt("%.9f", azimuth),  status};
}

std::string inspvaa(const PvaFields& p, unsigned header_week) {
  return ascii_frame('#', long_header("INSPVAA", header_week ? header_week : p.week, fmt("%.3f", p.seconds)),
                     p.fields());
}

std::string inspvasa(const PvaFields& p) {
  return ascii_frame('%', short_header("INSPVASA", p.week, fmt("%.3f", p.seconds)), p.fields());
}

std::vector<uint8_t> binary_frame(uint16_t id, unsigned week, uint32_t ms, const std::vector<uint8_t>& body,
                                  int length_override, int header_length_override) {
  std::vector<uint8_t> out = {0xAA, 0x44, 0x12};
  out.push_back(static_cast<uint8_t>(header_length_override >= 0 ? header_length_override : 28));
  le(&out, id, 2);
  out.push_back(0);     // message type: binary
  out.push_back(0x20);  // port
  le(&out, static_cast<uint64_t>(length_override >= 0 ? length_override : static_cast<int>(body.size())), 2);
  le(&out, 7, 2);        // sequence
  out.push_back(100);    // idle
  out.push_back(180);    // FINESTEERING
  le(&out, week, 2);
  le(&out, ms, 4);
  le(&out, 0x02000020, 4);
  le(&out, 0, 2);
  le(&out, 32768, 2);
  out.insert(out.end(), body.begin(), body.end());
  le(&out, bitwise_crc32(out.data(), out.size()), 4);
  return out;
}

std::vector<uint8_t> inspvab_body(const PvaFields& p, uint32_t status_code) {
  std::vector<uint8_t> body;
  le(&body, p.week, 4);
  for (double v : {p.seconds, p.lat, p.lon, p.height, p.vn, p.ve, p.vu, p.roll, p.pitch, p.azimuth})
    le_double(&body, v);
  le(&body, status_code, 4);
  return body;
}

std::vector<uint8_t> insstdevb_body(const std::vector<float>& sigmas, uint32_t ext_status, uint16_t since_update) {
  std::vector<uint8_t> body;
  for (float s : sigmas) le_float(&body, s);
  le(&body, ext_status, 4);
  le(&body, since_update, 2);
  le(&body, 0, 2);
  le(&body, 0, 4);
  le(&body, 0, 4);
  return body;
}

void append(std::vector<uint8_t>* out, const std::string& text) { out->insert(out->end(), text.begin(), text.end()); }
void append(std::vector<uint8_t>* out, const std::vector<uint8_t>& bytes) {
  out->insert(out->end(), bytes.begin(), bytes.end());
}

}  // namespace nadir::ins_bridge::testing
