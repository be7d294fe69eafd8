#include "processes/ins_bridge/novatel_encoder.h"

#include <algorithm>
#include <cstdio>

#include "processes/ins_bridge/crc32.h"
#include "processes/ins_bridge/little_endian.h"

namespace nadir::ins_bridge {
namespace {

std::string finish_ascii(const std::string& frame) {
  const uint32_t crc = novatel_crc32(reinterpret_cast<const uint8_t*>(frame.data()) + 1, frame.size() - 1);
  char tail[16];
  std::snprintf(tail, sizeof tail, "*%08x\r\n", crc);
  return frame + tail;
}

std::string long_header(const char* name, const NovatelHeader& h) {
  char text[256];
  std::snprintf(text, sizeof text, "#%s,%s,%u,%.1f,%s,%u,%.3f,%08x,0000,%u;", name, h.port.c_str(),
                static_cast<unsigned>(h.sequence), static_cast<double>(h.idle_percent), h.time_status.c_str(),
                h.gps_week, h.gps_seconds, h.receiver_status, static_cast<unsigned>(h.software_version));
  return text;
}

std::string pva_body(const InsPva& p) {
  const char* status = ins_status_name(p.status);
  char text[512];
  std::snprintf(text, sizeof text, "%u,%.9f,%.11f,%.11f,%.4f,%.4f,%.4f,%.4f,%.9f,%.9f,%.9f,%s", p.gps_week,
                p.gps_seconds, p.latitude_deg, p.longitude_deg, p.height_m, p.north_velocity, p.east_velocity,
                p.up_velocity, p.roll_deg, p.pitch_deg, p.azimuth_deg, status ? status : "INS_INACTIVE");
  return text;
}

std::vector<uint8_t> binary_frame(uint16_t id, const NovatelHeader& h, const std::vector<uint8_t>& body) {
  std::vector<uint8_t> out(kBinaryHeaderSize + body.size() + 4, 0);
  uint8_t* p = out.data();
  p[0] = 0xAA;
  p[1] = 0x44;
  p[2] = 0x12;
  p[3] = kBinaryHeaderSize;
  put_u16(p + 4, id);
  p[6] = 0;  // binary, original message
  p[7] = 0x20;  // COM1
  put_u16(p + 8, static_cast<uint16_t>(body.size()));
  put_u16(p + 10, h.sequence);
  p[12] = static_cast<uint8_t>(h.idle_percent * 2.0f);  // 0.5 % units
  p[13] = h.time_status_code;
  put_u16(p + 14, static_cast<uint16_t>(h.gps_week));
  put_u32(p + 16, static_cast<uint32_t>(h.gps_seconds * 1000.0 + 0.5));
  put_u32(p + 20, h.receiver_status);
  put_u16(p + 24, 0);
  put_u16(p + 26, h.software_version);
  std::copy(body.begin(), body.end(), out.begin() + kBinaryHeaderSize);
  put_u32(p + kBinaryHeaderSize + body.size(), novatel_crc32(p, kBinaryHeaderSize + body.size()));
  return out;
}

}  // namespace

std::string encode_inspva_ascii(const NovatelHeader& header, const InsPva& pva) {
  return finish_ascii(long_header("INSPVAA", header) + pva_body(pva));
}

std::string encode_inspvas_ascii(const InsPva& pva) {
  char head[64];
  std::snprintf(head, sizeof head, "%%INSPVASA,%u,%.3f;", pva.gps_week, pva.gps_seconds);
  return finish_ascii(head + pva_body(pva));
}

std::string encode_insstdev_ascii(const NovatelHeader& header, const InsStdDev& s) {
  char body[512];
  std::snprintf(body, sizeof body, "%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%x,%u,0,0,0",
                static_cast<double>(s.latitude_m), static_cast<double>(s.longitude_m), static_cast<double>(s.height_m),
                static_cast<double>(s.north_velocity), static_cast<double>(s.east_velocity),
                static_cast<double>(s.up_velocity), static_cast<double>(s.roll_deg), static_cast<double>(s.pitch_deg),
                static_cast<double>(s.azimuth_deg), s.extended_status, static_cast<unsigned>(s.time_since_update));
  return finish_ascii(long_header("INSSTDEVA", header) + body);
}

std::vector<uint8_t> encode_inspva_binary(const NovatelHeader& header, const InsPva& p) {
  std::vector<uint8_t> body(kInspvaBodySize, 0);
  put_u32(body.data(), p.gps_week);
  const double values[] = {p.gps_seconds,    p.latitude_deg,  p.longitude_deg, p.height_m,  p.north_velocity,
                           p.east_velocity,  p.up_velocity,   p.roll_deg,      p.pitch_deg, p.azimuth_deg};
  for (int i = 0; i < 10; ++i) put_f64(body.data() + 4 + 8 * i, values[i]);
  put_u32(body.data() + 84, static_cast<uint32_t>(p.status));
  return binary_frame(kInspvaId, header, body);
}

std::vector<uint8_t> encode_insstdev_binary(const NovatelHeader& header, const InsStdDev& s) {
  std::vector<uint8_t> body(kInsstdevBodySize, 0);
  const float values[] = {s.latitude_m,  s.longitude_m, s.height_m,  s.north_velocity, s.east_velocity,
                          s.up_velocity, s.roll_deg,    s.pitch_deg, s.azimuth_deg};
  for (int i = 0; i < 9; ++i) put_f32(body.data() + 4 * i, values[i]);
  put_u32(body.data() + 36, s.extended_status);
  put_u16(body.data() + 40, s.time_since_update);
  return binary_frame(kInsstdevId, header, body);
}

}  // namespace nadir::ins_bridge
