#include "processes/foxglove/foxglove_server.h"

#include <nlohmann/json.hpp>
#include <websocketpp/config/asio_no_tls.hpp>
#include <websocketpp/server.hpp>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <map>
#include <mutex>
#include <stdexcept>
#include <thread>

namespace nadir {
namespace {

using WsServer = websocketpp::server<websocketpp::config::asio>;
using websocketpp::connection_hdl;
using nlohmann::json;

constexpr const char* kSubprotocol = "foxglove.websocket.v1";
constexpr int kStatusError = 2;

int64_t steady_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

struct Client {
  std::string peer;
  std::map<uint32_t, int> subscriptions;  // subscription id -> channel id
  int protocol_errors = 0;
  int64_t over_buffer_since_ns = -1;      // -1: under its buffer
  bool closing = false;
};

}  // namespace

class FoxgloveServer::Impl {
 public:
  Impl(const FoxgloveServerOptions& options, std::vector<FoxgloveChannel> channels)
      : options_(options), channels_(std::move(channels)), subscribers_(channels_.size()) {
    for (auto& s : subscribers_) s = 0;
    server_.clear_access_channels(websocketpp::log::alevel::all);
    server_.clear_error_channels(websocketpp::log::elevel::all);
    server_.init_asio();
    server_.set_reuse_addr(true);
    server_.set_max_message_size(options_.max_client_message_bytes);
    server_.set_max_http_body_size(options_.max_client_message_bytes);
    server_.set_open_handshake_timeout(5000);
    server_.set_close_handshake_timeout(1000);
    server_.set_validate_handler([this](connection_hdl h) { return on_validate(h); });
    server_.set_open_handler([this](connection_hdl h) { on_open(h); });
    server_.set_close_handler([this](connection_hdl h) { on_close(h); });
    server_.set_fail_handler([this](connection_hdl h) { on_fail(h); });
    server_.set_message_handler([this](connection_hdl h, WsServer::message_ptr m) { on_message(h, m); });
    try {
      boost::system::error_code ec;
      const auto address = boost::asio::ip::make_address(options_.address, ec);
      if (ec) throw std::runtime_error("'" + options_.address + "' is not an IP address");
      server_.listen(boost::asio::ip::tcp::endpoint(address, static_cast<uint16_t>(options_.port)));
      server_.start_accept();
      port_ = server_.get_local_endpoint(ec).port();
    } catch (const std::exception& e) {
      throw std::runtime_error("foxglove server: cannot listen on " + options_.address + ":" +
                               std::to_string(options_.port) + ": " + e.what());
    }
    thread_ = std::thread([this] { server_.run(); });
  }

  ~Impl() {
    boost::asio::post(server_.get_io_service(), [this] {
      websocketpp::lib::error_code ec;
      server_.stop_listening(ec);
      for (auto& [hdl, client] : clients_) server_.close(hdl, websocketpp::close::status::going_away, "server stops", ec);
    });
    // Clients that do not answer the close handshake are cut after a while.
    for (int i = 0; i < 200 && connected_ > 0; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    server_.stop();
    thread_.join();
  }

  int port() const { return port_; }

  bool has_subscribers(int id) const {
    return id >= 0 && id < static_cast<int>(subscribers_.size()) && subscribers_[id] > 0;
  }

  void publish(int id, int64_t timestamp_ns, std::string payload) {
    if (!has_subscribers(id)) return;
    const int64_t size = static_cast<int64_t>(payload.size());
    if (pending_bytes_ + size > static_cast<int64_t>(options_.max_pending_bytes)) {
      ++dropped_pending_;
      return;
    }
    pending_bytes_ += size;
    boost::asio::post(server_.get_io_service(), [this, id, timestamp_ns, size, p = std::move(payload)] {
      deliver(id, timestamp_ns, p);
      pending_bytes_ -= size;
    });
  }

  FoxgloveServerCounts counts() const {
    FoxgloveServerCounts c;
    c.clients_connected = connected_;
    c.clients_total = total_;
    c.clients_rejected = rejected_;
    c.clients_slow_disconnected = slow_disconnected_;
    c.clients_protocol_disconnected = protocol_disconnected_;
    c.protocol_errors = protocol_errors_;
    c.messages_sent = sent_;
    c.messages_dropped_client = dropped_client_;
    c.messages_dropped_pending = dropped_pending_;
    c.bytes_sent = bytes_sent_;
    c.pending_bytes = pending_bytes_;
    std::lock_guard<std::mutex> lock(event_mutex_);
    c.last_event = last_event_;
    return c;
  }

 private:
  // Everything below runs on the server thread.

  void note_event(const std::string& text) {
    std::fprintf(stderr, "nadir_foxglove: %s\n", text.c_str());
    std::lock_guard<std::mutex> lock(event_mutex_);
    last_event_ = text;
  }

  bool on_validate(connection_hdl hdl) {
    WsServer::connection_ptr con = server_.get_con_from_hdl(hdl);
    for (const std::string& p : con->get_requested_subprotocols()) {
      if (p == kSubprotocol) {
        con->select_subprotocol(kSubprotocol);
        return true;
      }
    }
    refused_reason_ = std::string("no ") + kSubprotocol + " subprotocol requested";
    return false;  // on_fail counts it
  }

  void on_open(connection_hdl hdl) {
    WsServer::connection_ptr con = server_.get_con_from_hdl(hdl);
    Client client;
    client.peer = con->get_remote_endpoint();
    clients_[hdl] = client;
    ++connected_;
    ++total_;
    send_text(hdl, json{{"op", "serverInfo"},
                        {"name", options_.name},
                        {"capabilities", json::array()},
                        {"supportedEncodings", json::array()},
                        {"metadata", json::object()},
                        {"sessionId", std::to_string(session_)}});
    json list = json::array();
    for (size_t i = 0; i < channels_.size(); ++i) {
      list.push_back({{"id", i},
                      {"topic", channels_[i].topic},
                      {"encoding", "json"},
                      {"schemaName", channels_[i].schema_name},
                      {"schema", channels_[i].schema},
                      {"schemaEncoding", "jsonschema"}});
    }
    send_text(hdl, json{{"op", "advertise"}, {"channels", list}});
  }

  void forget(connection_hdl hdl) {
    auto it = clients_.find(hdl);
    if (it == clients_.end()) return;
    for (const auto& [sub, channel] : it->second.subscriptions) --subscribers_[channel];
    clients_.erase(it);
    --connected_;
  }

  void on_close(connection_hdl hdl) {
    websocketpp::lib::error_code ec;
    WsServer::connection_ptr con = server_.get_con_from_hdl(hdl, ec);
    if (ec) return forget(hdl);
    const auto code = con->get_remote_close_code();
    auto it = clients_.find(hdl);
    if (it != clients_.end() && !it->second.closing &&
        (code == websocketpp::close::status::message_too_big || code == websocketpp::close::status::protocol_error ||
         con->get_local_close_code() == websocketpp::close::status::message_too_big ||
         con->get_local_close_code() == websocketpp::close::status::protocol_error)) {
      ++protocol_disconnected_;
      note_event(it->second.peer + " disconnected: closed with " + std::to_string(con->get_local_close_code()) + " (" +
                 con->get_local_close_reason() + ")");
    }
    forget(hdl);
  }

  void on_fail(connection_hdl hdl) {
    websocketpp::lib::error_code ec;
    WsServer::connection_ptr con = server_.get_con_from_hdl(hdl, ec);
    if (!ec && clients_.count(hdl)) {
      ++protocol_disconnected_;
      note_event(clients_[hdl].peer + " failed: " + con->get_ec().message());
    } else if (!ec) {
      // The handshake failed: not HTTP, not a WebSocket upgrade, or refused by on_validate.
      ++rejected_;
      note_event(con->get_remote_endpoint() + " refused: " +
                 (refused_reason_.empty() ? con->get_ec().message() : refused_reason_));
    }
    refused_reason_.clear();
    forget(hdl);
  }

  void send_text(connection_hdl hdl, const json& message) {
    websocketpp::lib::error_code ec;
    server_.send(hdl, message.dump(), websocketpp::frame::opcode::text, ec);
  }

  void disconnect(connection_hdl hdl, Client& client, websocketpp::close::status::value code,
                  const std::string& why) {
    if (client.closing) return;
    client.closing = true;
    note_event(client.peer + " disconnected: " + why);
    websocketpp::lib::error_code ec;
    server_.close(hdl, code, why, ec);
  }

  void protocol_error(connection_hdl hdl, Client& client, const std::string& what) {
    ++protocol_errors_;
    ++client.protocol_errors;
    send_text(hdl, json{{"op", "status"}, {"level", kStatusError}, {"message", what}});
    if (client.protocol_errors >= options_.max_protocol_errors) {
      ++protocol_disconnected_;
      disconnect(hdl, client, websocketpp::close::status::policy_violation,
                 std::to_string(client.protocol_errors) + " bad requests (last: " + what + ")");
    }
  }

  void on_message(connection_hdl hdl, WsServer::message_ptr message) {
    auto it = clients_.find(hdl);
    if (it == clients_.end() || it->second.closing) return;
    Client& client = it->second;
    if (message->get_opcode() != websocketpp::frame::opcode::text) {
      protocol_error(hdl, client, "binary client messages are not supported (no clientPublish capability)");
      return;
    }
    const json request = json::parse(message->get_payload(), nullptr, false);
    if (request.is_discarded() || !request.is_object() || !request.contains("op") || !request["op"].is_string()) {
      protocol_error(hdl, client, "request is not a JSON object with a string 'op'");
      return;
    }
    const std::string op = request["op"];
    if (op == "subscribe") {
      subscribe(hdl, client, request);
    } else if (op == "unsubscribe") {
      unsubscribe(hdl, client, request);
    } else {
      protocol_error(hdl, client, "unsupported op '" + op + "'");
    }
  }

  void subscribe(connection_hdl hdl, Client& client, const json& request) {
    if (!request.contains("subscriptions") || !request["subscriptions"].is_array()) {
      protocol_error(hdl, client, "subscribe: 'subscriptions' is not an array");
      return;
    }
    for (const json& s : request["subscriptions"]) {
      if (!s.is_object() || !s.contains("id") || !s["id"].is_number_unsigned() || !s.contains("channelId") ||
          !s["channelId"].is_number_unsigned()) {
        protocol_error(hdl, client, "subscribe: each subscription needs unsigned 'id' and 'channelId'");
        continue;
      }
      const uint64_t id = s["id"], channel = s["channelId"];
      if (channel >= channels_.size()) {
        protocol_error(hdl, client, "subscribe: channel " + std::to_string(channel) + " is not advertised");
      } else if (id > UINT32_MAX || client.subscriptions.count(static_cast<uint32_t>(id))) {
        protocol_error(hdl, client, "subscribe: subscription id " + std::to_string(id) + " is in use or too large");
      } else {
        client.subscriptions[static_cast<uint32_t>(id)] = static_cast<int>(channel);
        ++subscribers_[channel];
      }
    }
  }

  void unsubscribe(connection_hdl hdl, Client& client, const json& request) {
    if (!request.contains("subscriptionIds") || !request["subscriptionIds"].is_array()) {
      protocol_error(hdl, client, "unsubscribe: 'subscriptionIds' is not an array");
      return;
    }
    for (const json& id : request["subscriptionIds"]) {
      auto sub = id.is_number_unsigned() ? client.subscriptions.find(id.get<uint32_t>()) : client.subscriptions.end();
      if (sub == client.subscriptions.end()) {
        protocol_error(hdl, client, "unsubscribe: unknown subscription id " + id.dump());
        continue;
      }
      --subscribers_[sub->second];
      client.subscriptions.erase(sub);
    }
  }

  void deliver(int channel, int64_t timestamp_ns, const std::string& payload) {
    const int64_t now = steady_ns();
    // Cut after the loop: terminating runs the close handler, which erases from clients_.
    std::vector<WsServer::connection_ptr> to_cut;
    for (auto& [hdl, client] : clients_) {
      if (client.closing) continue;
      for (const auto& [sub, ch] : client.subscriptions) {
        if (ch != channel) continue;
        websocketpp::lib::error_code ec;
        WsServer::connection_ptr con = server_.get_con_from_hdl(hdl, ec);
        if (ec) break;
        if (con->get_buffered_amount() > options_.max_client_buffer_bytes) {
          ++dropped_client_;
          if (client.over_buffer_since_ns < 0) client.over_buffer_since_ns = now;
          if (now - client.over_buffer_since_ns > static_cast<int64_t>(options_.slow_client_timeout_s * 1e9)) {
            ++slow_disconnected_;
            disconnect(hdl, client, websocketpp::close::status::policy_violation, "slow consumer");
            to_cut.push_back(con);  // the close frame would wait behind the unsent data
          }
          break;
        }
        client.over_buffer_since_ns = -1;
        std::string frame(13 + payload.size(), '\0');
        frame[0] = 0x01;  // messageData
        for (int i = 0; i < 4; ++i) frame[1 + i] = static_cast<char>((sub >> (8 * i)) & 0xff);
        for (int i = 0; i < 8; ++i)
          frame[5 + i] = static_cast<char>((static_cast<uint64_t>(timestamp_ns) >> (8 * i)) & 0xff);
        std::memcpy(&frame[13], payload.data(), payload.size());
        server_.send(hdl, frame, websocketpp::frame::opcode::binary, ec);
        if (!ec) {
          ++sent_;
          bytes_sent_ += static_cast<int64_t>(frame.size());
        }
      }
    }
    for (const WsServer::connection_ptr& con : to_cut) con->terminate(websocketpp::lib::error_code());
  }

  FoxgloveServerOptions options_;
  std::vector<FoxgloveChannel> channels_;
  std::vector<std::atomic<int>> subscribers_;
  WsServer server_;
  std::thread thread_;
  int port_ = 0;
  const int64_t session_ = steady_ns();
  std::map<connection_hdl, Client, std::owner_less<connection_hdl>> clients_;
  std::atomic<int64_t> connected_{0}, total_{0}, rejected_{0}, slow_disconnected_{0}, protocol_disconnected_{0},
      protocol_errors_{0}, sent_{0}, dropped_client_{0}, dropped_pending_{0}, bytes_sent_{0}, pending_bytes_{0};
  std::string refused_reason_;  // set by on_validate for the on_fail that follows
  mutable std::mutex event_mutex_;
  std::string last_event_;
};

FoxgloveServer::FoxgloveServer(const FoxgloveServerOptions& options, std::vector<FoxgloveChannel> channels)
    : impl_(std::make_unique<Impl>(options, std::move(channels))) {}
FoxgloveServer::~FoxgloveServer() = default;
int FoxgloveServer::port() const { return impl_->port(); }
bool FoxgloveServer::has_subscribers(int id) const { return impl_->has_subscribers(id); }
void FoxgloveServer::publish(int id, int64_t timestamp_ns, std::string payload) {
  impl_->publish(id, timestamp_ns, std::move(payload));
}
FoxgloveServerCounts FoxgloveServer::counts() const { return impl_->counts(); }

}  // namespace nadir
