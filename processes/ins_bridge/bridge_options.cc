#include "processes/ins_bridge/bridge_options.h"

#include <cmath>
#include <memory>
#include <vector>

namespace nadir::ins_bridge {
namespace {

Eigen::Vector3d get_vector3(const Config& section, const std::string& key, const Eigen::Vector3d& fallback) {
  if (!section.has(key)) return fallback;
  const std::vector<double> values = section.get<std::vector<double>>(key);
  if (values.size() != 3) throw section.error(key, "must have 3 numbers, has " + std::to_string(values.size()));
  return {values[0], values[1], values[2]};
}

}  // namespace

BridgeOptions BridgeOptions::from_config(const Config& root) {
  BridgeOptions o;
  o.source = root.source();
  const Config section = root.section_or_empty("ins_bridge");
  o.baud_mismatch_bytes = section.get_in_range<int>("baud_mismatch_bytes", o.baud_mismatch_bytes, 256, 1 << 20);

  const Config ins = section.section_or_empty("ins");
  SerialOptions ins_defaults;
  ins_defaults.device = "/dev/ttyUSB0";
  ins_defaults.baud = 460800;
  o.ins.serial = SerialOptions::from_config(ins, ins_defaults);
  o.ins.imu_to_body_rpy_deg = get_vector3(ins, "imu_to_body_rpy_deg", o.ins.imu_to_body_rpy_deg);
  o.ins.stddev_max_age_s = ins.get_in_range<double>("stddev_max_age_s", o.ins.stddev_max_age_s, 0.0, 60.0);
  o.ins.leap_seconds = ins.get_in_range<int>("leap_seconds", o.ins.leap_seconds, -1, 100);
  o.ins.min_plausible_week = ins.get_in_range<int>("min_plausible_week", o.ins.min_plausible_week, 0, 65535);
  const Config sync = ins.section_or_empty("clock_sync");
  o.ins.clock_sync.window_s = sync.get<double>("window_s", o.ins.clock_sync.window_s);
  o.ins.clock_sync.block_s = sync.get<double>("block_s", o.ins.clock_sync.block_s);
  o.ins.clock_sync.jump_threshold_us = sync.get<double>("jump_threshold_us", o.ins.clock_sync.jump_threshold_us);
  o.ins.clock_sync.min_delay_us = sync.get<double>("min_delay_us", o.ins.clock_sync.min_delay_us);
  o.ins.clock_sync.settle_s = sync.get<double>("settle_s", o.ins.clock_sync.settle_s);
  o.ins.clock_sync.step_confirm_s = sync.get<double>("step_confirm_s", o.ins.clock_sync.step_confirm_s);

  const Config alt = section.section_or_empty("altimeter");
  SerialOptions alt_defaults;
  alt_defaults.device = "/dev/ttyUSB1";
  o.altimeter.serial = SerialOptions::from_config(alt, alt_defaults);
  o.altimeter.protocol = alt.get<std::string>("protocol", o.altimeter.protocol);
  const Config nu = alt.section_or_empty("number_unit");
  o.altimeter.number_unit.prefix = nu.get<std::string>("prefix", "");
  o.altimeter.number_unit.unit = nu.get<std::string>("unit", "m");
  o.altimeter.number_unit.quality_prefix = nu.get<std::string>("quality_prefix", "");
  o.altimeter.number_unit.no_return_token = nu.get<std::string>("no_return_token", "");
  o.altimeter.min_range_m = alt.get<double>("min_range_m", o.altimeter.min_range_m);
  o.altimeter.max_range_m = alt.get<double>("max_range_m", o.altimeter.max_range_m);
  o.altimeter.min_signal_quality =
      alt.get_in_range<double>("min_signal_quality", o.altimeter.min_signal_quality, 0.0, 1.0);
  o.altimeter.latency_ms = alt.get_in_range<double>("latency_ms", o.altimeter.latency_ms, 0.0, 1000.0);
  o.altimeter.publish_parse_errors = alt.get<bool>("publish_parse_errors", o.altimeter.publish_parse_errors);

  const Config shared = root.section_or_empty("altimeter");
  o.altimeter.beam_body = get_vector3(shared, "beam_body", o.altimeter.beam_body);
  const double norm = o.altimeter.beam_body.norm();
  if (!(norm > 0.5 && norm < 2.0)) throw shared.error("beam_body", "must be a direction (norm near 1)");
  o.altimeter.beam_body /= norm;
  o.Check();
  return o;
}

void BridgeOptions::Check() const {
  ins.serial.Check(source, "ins_bridge.ins");
  altimeter.serial.Check(source, "ins_bridge.altimeter");
  try {
    ins.clock_sync.Check();
  } catch (const ConfigError& e) {
    throw ConfigError(source + ": ins_bridge.ins." + e.what());
  }
  for (int i = 0; i < 3; ++i) {
    require_option(std::fabs(ins.imu_to_body_rpy_deg[i]) <= 180.0, source, "ins_bridge.ins.imu_to_body_rpy_deg",
                   "angles must be in [-180, 180] deg");
  }
  require_option(altimeter.protocol == "lightware" || altimeter.protocol == "number_unit", source,
                 "ins_bridge.altimeter.protocol", "= '" + altimeter.protocol + "' must be lightware or number_unit");
  altimeter.number_unit.Check(source);
  require_option(altimeter.min_range_m >= 0 && altimeter.min_range_m < altimeter.max_range_m, source,
                 "ins_bridge.altimeter.min_range_m", "must be in [0, max_range_m)");
  require_option(altimeter.max_range_m <= 100000, source, "ins_bridge.altimeter.max_range_m", "must be <= 100000");
}

std::unique_ptr<AltimeterLineParser> make_altimeter_parser(const AltimeterOptions& options) {
  if (options.protocol == "number_unit") return std::make_unique<NumberUnitParser>(options.number_unit);
  return std::make_unique<LightwareAsciiParser>();
}

}  // namespace nadir::ins_bridge
