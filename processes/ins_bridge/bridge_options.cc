#include "processes/ins_bridge/bridge_options.h"

#include <cmath>
#include <memory>
#include <vector>

#include "common/sensor_calibration.h"

namespace nadir::ins_bridge {
namespace {

Eigen::Vector3d get_vector3(const Config& section, const std::string& key, const Eigen::Vector3d& fallback) {
  if (!section.has(key)) return fallback;
  const std::vector<double> values = section.get<std::vector<double>>(key);
  if (values.size() != 3) throw section.error(key, "must have 3 numbers, has " + std::to_string(values.size()));
  return {values[0], values[1], values[2]};
}

}  // namespace

BridgeOptions BridgeOptions::defaults() {
  BridgeOptions o;
  o.ins.serial.device = "/dev/ttyUSB0";
  o.ins.serial.baud = 460800;
  o.altimeter.serial.device = "/dev/ttyUSB1";
  return o;
}

const OptionsSchema<BridgeOptions>& BridgeOptions::schema() {
  using O = BridgeOptions;
  using I = InsOptions;
  using A = AltimeterOptions;
  using U = NumberUnitOptions;
  static const OptionsSchema<O> schema = [] {
    OptionsSchema<O> s("ins_bridge", "INS (NovAtel SPAN) and laser altimeter over serial lines -> INS, ALTIMETER.");
    s.number("baud_mismatch_bytes", 256, 1 << 20, "bytes", "bytes without a good frame/line: baud mismatch suspected",
             &O::baud_mismatch_bytes)
        .include("ins", SerialOptions::schema(), &O::ins, &I::serial)
        .numbers<3>("ins.imu_to_body_rpy_deg", -180.0, 180.0, "deg",
                    "R_imu_body as ZYX roll, pitch, yaw: body axes -> the SPAN output frame", &O::ins,
                    &I::imu_to_body_rpy_deg)
        .number("ins.stddev_max_age_s", 0.0, 60.0, "s", "attach INSSTDEV to INS samples this close in GPS time",
                &O::ins, &I::stddev_max_age_s)
        .number("ins.leap_seconds", -1, 100, "s", "GPS - UTC; -1: built-in table", &O::ins, &I::leap_seconds)
        .number("ins.min_plausible_week", 0, 65535, "weeks", "lower GPS weeks are taken as modulo 1024", &O::ins,
                &I::min_plausible_week)
        .include("ins.clock_sync", ClockSyncOptions::schema(), &O::ins, &I::clock_sync)
        .include("altimeter", SerialOptions::schema(), &O::altimeter, &A::serial)
        .choice<std::string>("altimeter.protocol", {{"lightware", "lightware"}, {"number_unit", "number_unit"}},
                             "line format: lightware (\"123.45 m 87%\") or number_unit", &O::altimeter, &A::protocol)
        .text("altimeter.number_unit.prefix", "number_unit: text before the number (e.g. D=)", &O::altimeter,
              &A::number_unit, &U::prefix)
        .choice<std::string>("altimeter.number_unit.unit", {{"m", "m"}, {"cm", "cm"}, {"mm", "mm"}, {"ft", "ft"}},
                             "number_unit: unit of the number", &O::altimeter, &A::number_unit, &U::unit)
        .text("altimeter.number_unit.quality_prefix", "number_unit: text before the 0..100 quality (empty: none)",
              &O::altimeter, &A::number_unit, &U::quality_prefix)
        .text("altimeter.number_unit.no_return_token", "number_unit: the device's no-return line (empty: none)",
              &O::altimeter, &A::number_unit, &U::no_return_token)
        .number("altimeter.min_range_m", 0.0, 1e5, "m", "outside [min, max]: published VALID_OUT_OF_RANGE",
                &O::altimeter, &A::min_range_m)
        .number("altimeter.max_range_m", 0.0, 1e5, "m", "... upper end", &O::altimeter, &A::max_range_m)
        .number("altimeter.min_signal_quality", 0.0, 1.0, "", "below (when reported): VALID_LOW_SIGNAL",
                &O::altimeter, &A::min_signal_quality)
        .number("altimeter.latency_ms", 0.0, 1000.0, "ms", "measurement -> first byte of its line", &O::altimeter,
                &A::latency_ms)
        .flag("altimeter.publish_parse_errors", "unparsable lines published as VALID_PARSE_ERROR", &O::altimeter,
              &A::publish_parse_errors)
        .rule("altimeter.min_range_m", [](const O& o) { return o.altimeter.min_range_m < o.altimeter.max_range_m; },
              "must be below max_range_m");
    return s;
  }();
  return schema;
}

BridgeOptions BridgeOptions::from_config(const Config& root) {
  BridgeOptions o = defaults();
  o.source = root.source();
  schema().read(root.section_or_empty("ins_bridge"), &o);

  const Config shared = root.section_or_empty("altimeter");
  shared.require_known_keys(SensorCalibration::altimeter_keys());
  o.altimeter.beam_body = get_vector3(shared, "beam_body", o.altimeter.beam_body);
  const double norm = o.altimeter.beam_body.norm();
  if (!(norm > 0.5 && norm < 2.0)) throw shared.error("beam_body", "must be a direction (norm near 1)");
  o.altimeter.beam_body /= norm;
  o.Check();
  return o;
}

void BridgeOptions::Check() const {
  schema().check(*this, Config(YAML::Node(YAML::NodeType::Map), source, "ins_bridge"));
}

std::unique_ptr<AltimeterLineParser> make_altimeter_parser(const AltimeterOptions& options) {
  if (options.protocol == "number_unit") return std::make_unique<NumberUnitParser>(options.number_unit);
  return std::make_unique<LightwareAsciiParser>();
}

}  // namespace nadir::ins_bridge
