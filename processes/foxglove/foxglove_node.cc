#include "processes/foxglove/foxglove_node.h"

#include <cstdio>

#include "processes/foxglove/foxglove_schemas.h"

namespace nadir {
namespace {

FoxgloveTranslatorOptions translator_options(const FoxgloveOptions& o) {
  FoxgloveTranslatorOptions t;
  t.origin_from_ins = o.origin_from_ins;
  t.origin = {o.origin_latitude_deg, o.origin_longitude_deg, o.origin_height_m};
  t.image_rate_hz = o.image_rate_hz;
  return t;
}

FoxgloveServerOptions server_options(const FoxgloveOptions& o) {
  FoxgloveServerOptions s;
  s.address = o.address;
  s.port = o.port;
  s.max_client_buffer_bytes = static_cast<size_t>(o.max_client_buffer_kb) << 10;
  s.slow_client_timeout_s = o.slow_client_timeout_s;
  s.max_pending_bytes = static_cast<size_t>(o.max_pending_kb) << 10;
  s.max_client_message_bytes = static_cast<size_t>(o.max_client_message_kb) << 10;
  s.max_protocol_errors = o.max_protocol_errors;
  return s;
}

}  // namespace

FoxgloveNode::FoxgloveNode(const FoxgloveOptions& options, Bus& bus) : translator_(translator_options(options)) {
  options.Check();
  std::vector<FoxgloveChannel> channels;
  for (const FoxgloveTopic& t : translator_.topics())
    channels.push_back({t.name, t.schema_name, foxglove_schemas::schema_text(t.schema_name)});
  FoxgloveServerOptions server = server_options(options);
  try {
    server_ = std::make_unique<FoxgloveServer>(server, channels);
  } catch (const std::runtime_error& e) {
    // The port is taken (another replay or process set being watched): a
    // viewer's port is no reason to stop the flight, so any free one is used
    // and named. An address that cannot be listened on at all still throws.
    if (server.port == 0) throw;
    server.port = 0;
    try {
      server_ = std::make_unique<FoxgloveServer>(server, std::move(channels));
    } catch (const std::runtime_error&) {
      throw e;  // not the port: the first error says what is wrong
    }
    port_note_ = "port " + std::to_string(options.port) + " was taken, serving on " + std::to_string(server_->port());
    std::printf("nadir_foxglove: %s (%s)\n", port_note_.c_str(), e.what());
  }
  // Where to point Foxglove (and, with port 0, which port was chosen).
  std::printf("nadir_foxglove: serving ws://%s:%d\n", options.address.c_str(), server_->port());
  std::fflush(stdout);
  for (const std::string& channel : translator_.lcm_channels()) {
    bus.subscribe_raw(channel, [this](const std::string& ch, const uint8_t* data, size_t size) {
      on_message(ch, data, size);
    });
  }
}

void FoxgloveNode::on_message(const std::string& channel, const uint8_t* data, size_t size) {
  ++received_;
  scratch_.clear();
  std::string reason;
  if (!translator_.translate(
          channel, data, size, [this](int topic) { return server_->has_subscribers(topic); }, &scratch_, &reason)) {
    ++undecodable_;
    last_decode_error_ = channel + ": " + reason;
    return;
  }
  for (FoxgloveMessage& m : scratch_) server_->publish(m.topic, m.time_ns, std::move(m.json));
}

StatusReport FoxgloveNode::status() const {
  const FoxgloveServerCounts c = server_->counts();
  StatusReport r;
  r.received = received_;
  r.published = c.messages_sent;
  r.dropped = c.messages_dropped_client + c.messages_dropped_pending;
  r.errors = c.protocol_errors + undecodable_;
  // WARN for the period in which a client misbehaved or messages were dropped.
  const bool trouble = c.clients_rejected > last_counts_.clients_rejected ||
                       c.clients_slow_disconnected > last_counts_.clients_slow_disconnected ||
                       c.clients_protocol_disconnected > last_counts_.clients_protocol_disconnected ||
                       c.protocol_errors > last_counts_.protocol_errors || r.dropped > last_counts_.messages_dropped_client +
                                                                                              last_counts_.messages_dropped_pending;
  if (trouble) {
    r.state = status_t::STATE_WARN;
    r.detail = c.last_event.empty() ? "messages dropped for slow clients" : c.last_event;
  } else if (!last_decode_error_.empty() && undecodable_ > 0) {
    r.detail = "undecodable: " + last_decode_error_;
  } else if (!port_note_.empty()) {
    r.detail = port_note_;
  }
  last_counts_ = c;
  r.counters = {{"port", static_cast<double>(server_->port())},
                {"clients_connected", static_cast<double>(c.clients_connected)},
                {"clients_total", static_cast<double>(c.clients_total)},
                {"clients_rejected", static_cast<double>(c.clients_rejected)},
                {"clients_slow_disconnected", static_cast<double>(c.clients_slow_disconnected)},
                {"clients_protocol_disconnected", static_cast<double>(c.clients_protocol_disconnected)},
                {"protocol_errors", static_cast<double>(c.protocol_errors)},
                {"messages_dropped_client", static_cast<double>(c.messages_dropped_client)},
                {"messages_dropped_pending", static_cast<double>(c.messages_dropped_pending)},
                {"pending_kb", c.pending_bytes / 1024.0},
                {"sent_mb", c.bytes_sent / 1048576.0},
                {"undecodable", static_cast<double>(undecodable_)},
                {"images_decimated", static_cast<double>(translator_.images_decimated())}};
  return r;
}

std::unique_ptr<Node> make_foxglove_node(const Config& root, Bus& bus) {
  return std::make_unique<FoxgloveNode>(FoxgloveOptions::from_config(root), bus);
}

void register_foxglove_node(NodeRegistry& registry) { registry.add("foxglove", make_foxglove_node); }

}  // namespace nadir
