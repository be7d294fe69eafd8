#pragma once
// Options of nadir_ins_bridge, read from the `ins_bridge:` section (and the
// shared `altimeter.beam_body`) of the config. Check() throws ConfigError
// naming the key and the allowed range.

#include <Eigen/Core>

#include <string>

#include "common/clock_sync.h"
#include "common/config.h"
#include "common/serial_port.h"
#include "processes/ins_bridge/altimeter_parser.h"

namespace nadir::ins_bridge {

struct InsOptions {
  SerialOptions serial;
  Eigen::Vector3d imu_to_body_rpy_deg = Eigen::Vector3d::Zero();
  double stddev_max_age_s = 2.0;  // INSSTDEV older than this is not attached
  int leap_seconds = -1;          // GPS - UTC; -1: built-in table
  int min_plausible_week = 2048;  // weeks below this are taken as modulo 1024
  ClockSyncOptions clock_sync;
};

struct AltimeterOptions {
  SerialOptions serial;
  std::string protocol = "lightware";  // lightware | number_unit
  NumberUnitOptions number_unit;
  double min_range_m = 0.2;
  double max_range_m = 1500.0;
  double min_signal_quality = 0.0;   // below: VALID_LOW_SIGNAL (when the device reports it)
  double latency_ms = 0.0;           // measurement to start of line
  bool publish_parse_errors = true;  // publish unparsable lines flagged VALID_PARSE_ERROR
  Eigen::Vector3d beam_body = Eigen::Vector3d::UnitZ();
};

struct BridgeOptions {
  InsOptions ins;
  AltimeterOptions altimeter;
  // Bytes without one good frame/line after which a baud mismatch is suspected.
  int baud_mismatch_bytes = 2048;

  // `root` is the whole config (ins_bridge: and altimeter: sections).
  static BridgeOptions from_config(const Config& root);
  void Check() const;
  static const OptionsSchema<BridgeOptions>& schema();  // every key of `ins_bridge:`
  static BridgeOptions defaults();  // what an absent key means (each serial line's device and rate)
  std::string source = "<defaults>";
};

std::unique_ptr<AltimeterLineParser> make_altimeter_parser(const AltimeterOptions& options);

}  // namespace nadir::ins_bridge
