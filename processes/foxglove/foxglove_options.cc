#include "processes/foxglove/foxglove_options.h"

namespace nadir {

const OptionsSchema<FoxgloveOptions>& FoxgloveOptions::schema() {
  using O = FoxgloveOptions;
  static const OptionsSchema<O> schema = [] {
    OptionsSchema<O> s("foxglove", "The Foxglove WebSocket bridge (nadir_foxglove) and the MCAP export's topics.");
    s.text("address", "the server's IPv4 address: loopback by default, 0.0.0.0 for every interface", &O::address)
        .number("port", 0, 65535, "", "TCP port; 0: any free port (printed at start, STATUS counter port)", &O::port)
        .number("image_rate_hz", 0.0, 1000.0, "Hz", "CAMERA_IMAGE forwarded at most this often (sensor time); 0: every frame",
                &O::image_rate_hz)
        .flag("origin_from_ins", "POSE's NED origin on the globe is the INS position at the first POSE; false: the one below",
              &O::origin_from_ins)
        .number("origin_latitude_deg", -90.0, 90.0, "deg", "origin latitude when origin_from_ins is false",
                &O::origin_latitude_deg)
        .number("origin_longitude_deg", -180.0, 180.0, "deg", "origin longitude when origin_from_ins is false",
                &O::origin_longitude_deg)
        .number("origin_height_m", -1000.0, 20000.0, "m", "origin height when origin_from_ins is false",
                &O::origin_height_m)
        .number("max_client_buffer_kb", 64, 1 << 20, "KiB", "a client with more unsent data is skipped (its messages dropped)",
                &O::max_client_buffer_kb)
        .above("slow_client_timeout_s", 0.0, 600.0, "s", "a client skipped this long is disconnected",
               &O::slow_client_timeout_s)
        .number("max_pending_kb", 64, 1 << 21, "KiB", "messages between the LCM and the server thread; beyond, dropped",
                &O::max_pending_kb)
        .number("max_client_message_kb", 1, 16384, "KiB", "larger client frames close the connection (1009)",
                &O::max_client_message_kb)
        .number("max_protocol_errors", 1, 1000000, "", "bad requests (not JSON, unknown op or channel) before disconnecting",
                &O::max_protocol_errors)
        .rule("address", [](const O& o) { return !o.address.empty(); },
              "is empty (e.g. 127.0.0.1, or 0.0.0.0 for every interface)");
    return s;
  }();
  return schema;
}

FoxgloveOptions FoxgloveOptions::from_config(const Config& root) {
  return schema().read(root.section_or_empty("foxglove"));
}

void FoxgloveOptions::Check() const { schema().check(*this); }

}  // namespace nadir
