#pragma once
// Options of the Foxglove bridge (config section `foxglove:`), each documented
// where it is declared. Check() throws ConfigError naming the key and range.

#include <string>

#include "common/config.h"
#include "common/options_schema.h"

namespace nadir {

struct FoxgloveOptions {
  // WebSocket server. Loopback by default: nothing leaves the host unless
  // configured (0.0.0.0 serves every interface). Port 0: any free port (the
  // chosen one is printed and reported in STATUS).
  std::string address = "127.0.0.1";
  int port = 8765;
  // CAMERA_IMAGE is forwarded at most this often (sensor time), 0: every frame.
  double image_rate_hz = 2.0;
  // POSE's local NED origin on the globe (the Map panel's LocationFix): the
  // INS position at the first POSE, or the configured one when
  // origin_from_ins is false.
  bool origin_from_ins = true;
  double origin_latitude_deg = 0.0;
  double origin_longitude_deg = 0.0;
  double origin_height_m = 0.0;
  // A client whose unsent data exceeds this is skipped (messages dropped for
  // it alone); one that stays over it for slow_client_timeout_s is disconnected.
  int max_client_buffer_kb = 8192;
  double slow_client_timeout_s = 3.0;
  // Messages handed from the LCM thread to the server thread and not yet sent:
  // beyond, new ones are dropped (memory stays bounded whatever the clients do).
  int max_pending_kb = 32768;
  // Client frames larger than this close the connection (1009).
  int max_client_message_kb = 64;
  // Malformed or unsupported client requests tolerated before disconnecting.
  int max_protocol_errors = 10;

  static const OptionsSchema<FoxgloveOptions>& schema();  // every key of `foxglove:` (options_schema.h)
  static FoxgloveOptions from_config(const Config& root);
  void Check() const;  // throws ConfigError naming the key
};

}  // namespace nadir
