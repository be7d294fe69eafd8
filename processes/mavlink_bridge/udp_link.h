#pragma once
// One UDP socket for MAVLink: as a server (bound, answers whoever sent last,
// as an autopilot's companion link is usually set up) or as a client (sends
// to a fixed address). Non-blocking; every datagram holds whole frames.

#include <netinet/in.h>

#include <cstdint>
#include <string>
#include <vector>

namespace nadir::mavlink_bridge {

// "a.b.c.d:port" (numeric IPv4). False with `why` when malformed; `out` may be null.
bool parse_udp_endpoint(const std::string& text, sockaddr_in* out, std::string* why);

class UdpLink {
 public:
  UdpLink(bool server, std::string local, std::string remote);
  ~UdpLink();
  UdpLink(const UdpLink&) = delete;
  UdpLink& operator=(const UdpLink&) = delete;

  // Throws std::runtime_error naming the address when the socket cannot be bound.
  void open();
  int fd() const { return fd_; }
  uint16_t local_port() const;
  // One datagram, or false when none is waiting.
  bool receive(std::vector<uint8_t>* datagram);
  // False when there is nobody to send to yet (server before the first
  // datagram) or the send failed (counted).
  bool send(const uint8_t* data, size_t size);
  bool has_peer() const { return have_peer_; }
  std::string peer() const;
  int64_t datagrams_in() const { return datagrams_in_; }
  int64_t datagrams_out() const { return datagrams_out_; }
  int64_t send_failures() const { return send_failures_; }
  const std::string& last_error() const { return last_error_; }

 private:
  bool server_;
  std::string local_;
  std::string remote_;
  int fd_ = -1;
  sockaddr_in peer_{};
  bool have_peer_ = false;
  int64_t datagrams_in_ = 0;
  int64_t datagrams_out_ = 0;
  int64_t send_failures_ = 0;
  std::string last_error_;
};

}  // namespace nadir::mavlink_bridge
