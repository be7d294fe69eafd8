#pragma once
// A sensor outage cut into a simulated flight, so that faults are tests and
// not one-off experiments: the altimeter returns nothing (VALID_NO_RETURN, as
// a real one over water or beyond range), the INS or the camera stops
// publishing, or the ground loses its texture (image contrast cut to a
// fraction about the image mean: snow, calm water, haze). Noise draws go on
// during an outage, so everything outside it is the same as without it.

#include <string>
#include <vector>

namespace nadir::sim {

struct SensorOutage {
  enum class Kind { kAltimeter, kIns, kCamera, kTexture };
  Kind kind = Kind::kAltimeter;
  double start_s = 0.0;     // flight time
  double duration_s = 0.0;
  double contrast = 0.03;   // texture: remaining fraction of the contrast

  bool covers(double t_s) const { return t_s >= start_s && t_s < start_s + duration_s; }
  // "KIND:START:DURATION[:CONTRAST]", KIND one of altimeter, ins, camera,
  // texture; throws std::invalid_argument naming the text and what is wrong.
  static SensorOutage parse(const std::string& text);
  std::string name() const;
};

// True when one of `outages` of `kind` covers flight time t_s.
const SensorOutage* find_outage(const std::vector<SensorOutage>& outages, SensorOutage::Kind kind, double t_s);

// Scales an 8-bit image's contrast about its mean (texture outages).
void cut_contrast(double contrast, std::vector<uint8_t>* pixels);

}  // namespace nadir::sim
