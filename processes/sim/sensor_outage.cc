#include "processes/sim/sensor_outage.h"

#include <cmath>
#include <cstdint>
#include <sstream>
#include <stdexcept>

namespace nadir::sim {
namespace {

double parse_number(const std::string& text, const std::string& field, const std::string& whole) {
  size_t used = 0;
  double value = 0.0;
  try {
    value = std::stod(field, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != field.size() || !std::isfinite(value)) {
    throw std::invalid_argument("--outage '" + whole + "': " + text + " '" + field + "' is not a number");
  }
  return value;
}

}  // namespace

SensorOutage SensorOutage::parse(const std::string& text) {
  std::vector<std::string> fields;
  std::istringstream in(text);
  std::string field;
  while (std::getline(in, field, ':')) fields.push_back(field);
  if (fields.size() < 3 || fields.size() > 4) {
    throw std::invalid_argument("--outage '" + text + "': expected KIND:START_S:DURATION_S[:CONTRAST]");
  }
  SensorOutage o;
  if (fields[0] == "altimeter") {
    o.kind = Kind::kAltimeter;
  } else if (fields[0] == "ins") {
    o.kind = Kind::kIns;
  } else if (fields[0] == "camera") {
    o.kind = Kind::kCamera;
  } else if (fields[0] == "texture") {
    o.kind = Kind::kTexture;
  } else {
    throw std::invalid_argument("--outage '" + text + "': unknown kind '" + fields[0] +
                                "' (altimeter, ins, camera, texture)");
  }
  o.start_s = parse_number("start", fields[1], text);
  o.duration_s = parse_number("duration", fields[2], text);
  if (o.start_s < 0.0 || o.duration_s <= 0.0) {
    throw std::invalid_argument("--outage '" + text + "': start must be >= 0 and duration > 0");
  }
  if (fields.size() == 4) {
    if (o.kind != Kind::kTexture) throw std::invalid_argument("--outage '" + text + "': only texture has a contrast");
    o.contrast = parse_number("contrast", fields[3], text);
    if (o.contrast < 0.0 || o.contrast > 1.0) {
      throw std::invalid_argument("--outage '" + text + "': contrast must be in [0, 1]");
    }
  }
  return o;
}

std::string SensorOutage::name() const {
  switch (kind) {
    case Kind::kAltimeter:
      return "altimeter";
    case Kind::kIns:
      return "ins";
    case Kind::kCamera:
      return "camera";
    case Kind::kTexture:
      return "texture";
  }
  return "?";
}

const SensorOutage* find_outage(const std::vector<SensorOutage>& outages, SensorOutage::Kind kind, double t_s) {
  for (const SensorOutage& o : outages) {
    if (o.kind == kind && o.covers(t_s)) return &o;
  }
  return nullptr;
}

void cut_contrast(double contrast, std::vector<uint8_t>* pixels) {
  if (pixels->empty()) return;
  uint64_t sum = 0;
  for (const uint8_t p : *pixels) sum += p;
  const double mean = static_cast<double>(sum) / static_cast<double>(pixels->size());
  for (uint8_t& p : *pixels) {
    const double v = mean + contrast * (static_cast<double>(p) - mean);
    p = static_cast<uint8_t>(std::lround(std::min(255.0, std::max(0.0, v))));
  }
}

}  // namespace nadir::sim
