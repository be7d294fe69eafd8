#pragma once
// A Foxglove WebSocket protocol server (foxglove.websocket.v1) on its own
// thread: advertises a fixed set of JSON channels, takes subscribe and
// unsubscribe requests, and sends each published message to the clients
// subscribed to its channel.
//
// publish() is called from the LCM thread and never blocks on a client: the
// message is handed to the server thread through a queue bounded in bytes
// (beyond, it is dropped and counted). A client whose unsent data exceeds its
// buffer is skipped; one that stays over it too long is disconnected. Bad
// requests (not JSON, unknown ops, unknown channels, binary frames) are
// answered with a status message and counted; past max_protocol_errors the
// client is disconnected. Oversized frames and WebSocket protocol errors
// close the connection. The server stays up in every case.

#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace nadir {

struct FoxgloveServerOptions {
  std::string address = "127.0.0.1";
  int port = 8765;                      // 0: any free port (see port())
  std::string name = "nadir_foxglove";  // serverInfo name
  size_t max_client_buffer_bytes = 8u << 20;
  double slow_client_timeout_s = 3.0;
  size_t max_pending_bytes = 32u << 20;
  size_t max_client_message_bytes = 64u << 10;
  int max_protocol_errors = 10;
};

struct FoxgloveChannel {
  std::string topic;
  std::string schema_name;
  std::string schema;  // JSON Schema text
};

// Counters since start (read from any thread).
struct FoxgloveServerCounts {
  int64_t clients_connected = 0;     // now
  int64_t clients_total = 0;         // accepted since start
  int64_t clients_rejected = 0;      // handshakes refused (no foxglove.websocket.v1 subprotocol)
  int64_t clients_slow_disconnected = 0;
  int64_t clients_protocol_disconnected = 0;  // too many bad requests, oversized or invalid frames
  int64_t protocol_errors = 0;       // bad requests answered with a status message
  int64_t messages_sent = 0;         // per client
  int64_t messages_dropped_client = 0;   // skipped for a client over its buffer
  int64_t messages_dropped_pending = 0;  // dropped before the server thread (queue full)
  int64_t bytes_sent = 0;
  int64_t pending_bytes = 0;         // now
  std::string last_event;            // the last client trouble, e.g. "127.0.0.1:40112 disconnected: slow consumer"
};

class FoxgloveServer {
 public:
  // Binds and starts serving; throws std::runtime_error naming the address
  // and port when it cannot listen.
  FoxgloveServer(const FoxgloveServerOptions& options, std::vector<FoxgloveChannel> channels);
  ~FoxgloveServer();  // closes every connection and joins the thread
  FoxgloveServer(const FoxgloveServer&) = delete;
  FoxgloveServer& operator=(const FoxgloveServer&) = delete;

  int port() const;  // the bound port
  // Whether any client is subscribed to channel `id` (index into channels):
  // lets the caller skip encoding what nobody wants.
  bool has_subscribers(int id) const;
  // Thread-safe, never blocks; `timestamp_ns` goes into the message frame.
  void publish(int id, int64_t timestamp_ns, std::string payload);
  FoxgloveServerCounts counts() const;

 private:
  class Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace nadir
