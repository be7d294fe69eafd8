#pragma once
// Writes NovAtel logs the way a SPAN receiver does, for the serial simulator
// (tools/sim_serial) and round-trip tests. Parser tests generate their own
// sentences independently of this file.

#include <cstdint>
#include <string>
#include <vector>

#include "processes/ins_bridge/novatel_messages.h"

namespace nadir::ins_bridge {

// Header fields a receiver fills in; the time is the log's time.
struct NovatelHeader {
  std::string port = "COM1";
  uint16_t sequence = 0;
  float idle_percent = 50.0f;
  std::string time_status = "FINESTEERING";
  uint8_t time_status_code = 180;  // FINESTEERING in binary
  uint32_t gps_week = 0;
  double gps_seconds = 0.0;
  uint32_t receiver_status = 0;
  uint16_t software_version = 0;
};

// "#INSPVAA,...;...*xxxxxxxx\r\n"
std::string encode_inspva_ascii(const NovatelHeader& header, const InsPva& pva);
// "%INSPVASA,week,seconds;...*xxxxxxxx\r\n"
std::string encode_inspvas_ascii(const InsPva& pva);
std::string encode_insstdev_ascii(const NovatelHeader& header, const InsStdDev& stddev);
std::vector<uint8_t> encode_inspva_binary(const NovatelHeader& header, const InsPva& pva);
std::vector<uint8_t> encode_insstdev_binary(const NovatelHeader& header, const InsStdDev& stddev);

}  // namespace nadir::ins_bridge
