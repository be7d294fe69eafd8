#pragma once
// Where nadir_sim_serial's INS and altimeter samples come from: a simulator
// LCM log (INS and ALTIMETER channels, as the real bridge would publish them)
// or a flight generated here. Samples come out in time order.

#include <cstdint>
#include <memory>
#include <string>

#include "nadir/altimeter_t.hpp"
#include "nadir/ins_t.hpp"

namespace nadir::sim_serial {

struct Sample {
  enum class Kind { kIns, kAltimeter };
  Kind kind = Kind::kIns;
  int64_t t_us = 0;     // sensor time in the source (log utime or generated time)
  ins_t ins;            // kind == kIns (project frames, radians)
  altimeter_t altimeter;  // kind == kAltimeter
};

class FlightSource {
 public:
  virtual ~FlightSource() = default;
  // Next sample in time order; false at the end.
  virtual bool next(Sample* sample) = 0;
  virtual std::string describe() const = 0;
};

// Reads INS and ALTIMETER from an LCM log (common/log_file.h LogReader; damage
// is skipped and reported by describe()). Messages that fail to decode are counted.
std::unique_ptr<FlightSource> make_log_source(const std::string& path);

struct GeneratedFlightOptions {
  double duration_s = 600.0;
  double ins_rate_hz = 100.0;
  double altimeter_rate_hz = 10.0;
  double speed_mps = 30.0;
  double height_agl_m = 300.0;
  double turn_radius_m = 2000.0;
  double terrain_height_m = 400.0;  // flat ground, ellipsoidal
  double latitude_deg = 47.0;
  double longitude_deg = 8.5;
  double beam_body[3] = {0, 0, 1};
  uint64_t seed = 1;                // altimeter noise and dropouts
};
// A level circle (coordinated turn) with a slow pitch oscillation over flat ground.
std::unique_ptr<FlightSource> make_generated_source(const GeneratedFlightOptions& options);

}  // namespace nadir::sim_serial
