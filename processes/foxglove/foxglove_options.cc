#include "processes/foxglove/foxglove_options.h"

namespace nadir {

FoxgloveOptions FoxgloveOptions::from_config(const Config& root) {
  const Config c = root.section_or_empty("foxglove");
  c.require_known_keys({"address", "port", "image_rate_hz", "origin_from_ins", "origin_latitude_deg", "origin_longitude_deg",
                        "origin_height_m", "max_client_buffer_kb", "slow_client_timeout_s", "max_pending_kb",
                        "max_client_message_kb", "max_protocol_errors"});
  FoxgloveOptions o;
  o.address = c.get<std::string>("address", o.address);
  if (o.address.empty()) throw c.error("address", "is empty (e.g. 127.0.0.1, or 0.0.0.0 for every interface)");
  o.port = c.get_in_range("port", o.port, 0, 65535);
  o.image_rate_hz = c.get_in_range("image_rate_hz", o.image_rate_hz, 0.0, 1000.0);
  o.origin_from_ins = c.get<bool>("origin_from_ins", o.origin_from_ins);
  o.origin_latitude_deg = c.get_in_range("origin_latitude_deg", o.origin_latitude_deg, -90.0, 90.0);
  o.origin_longitude_deg = c.get_in_range("origin_longitude_deg", o.origin_longitude_deg, -180.0, 180.0);
  o.origin_height_m = c.get_in_range("origin_height_m", o.origin_height_m, -1000.0, 20000.0);
  o.max_client_buffer_kb = c.get_in_range("max_client_buffer_kb", o.max_client_buffer_kb, 64, 1 << 20);
  o.slow_client_timeout_s = c.get_in_range("slow_client_timeout_s", o.slow_client_timeout_s, 0.1, 600.0);
  o.max_pending_kb = c.get_in_range("max_pending_kb", o.max_pending_kb, 64, 1 << 21);
  o.max_client_message_kb = c.get_in_range("max_client_message_kb", o.max_client_message_kb, 1, 16384);
  o.max_protocol_errors = c.get_in_range("max_protocol_errors", o.max_protocol_errors, 1, 1000000);
  return o;
}

void FoxgloveOptions::Check() const {
  // from_config checks each key as it reads it; options built in code (tests,
  // the exporter) are checked here with the same ranges.
  auto require = [](bool ok, const char* key, const char* what) {
    if (!ok) throw ConfigError(std::string("foxglove options: key 'foxglove.") + key + "' " + what);
  };
  require(!address.empty(), "address", "is empty");
  require(port >= 0 && port <= 65535, "port", "is out of range [0, 65535]");
  require(image_rate_hz >= 0, "image_rate_hz", "is negative");
  require(origin_latitude_deg >= -90 && origin_latitude_deg <= 90, "origin_latitude_deg", "is out of range [-90, 90]");
  require(origin_longitude_deg >= -180 && origin_longitude_deg <= 180, "origin_longitude_deg",
          "is out of range [-180, 180]");
  require(max_client_buffer_kb >= 64, "max_client_buffer_kb", "is below 64");
  require(slow_client_timeout_s > 0, "slow_client_timeout_s", "is not positive");
  require(max_pending_kb >= 64, "max_pending_kb", "is below 64");
  require(max_client_message_kb >= 1, "max_client_message_kb", "is below 1");
  require(max_protocol_errors >= 1, "max_protocol_errors", "is below 1");
}

}  // namespace nadir
