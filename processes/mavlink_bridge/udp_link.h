#pragma once
// One UDP socket for MAVLink: as a server (bound, answers the autopilot at the
// address its last valid frame came from, as an autopilot's companion link is
// usually set up) or as a client (sends to a fixed address). Non-blocking;
// every datagram holds whole frames. The socket never picks its reply address
// itself: a datagram's sender becomes the peer only when the caller says its
// frames were the autopilot's (set_peer), so a stray or forged datagram from
// another port diverts nothing. A server may also be pinned to the
// autopilot's address: then it answers only there from the start and drops,
// counted, every datagram from any other sender before it is decoded.

#include <netinet/in.h>

#include <cstdint>
#include <string>
#include <vector>

namespace nadir::mavlink_bridge {

// "a.b.c.d:port" (numeric IPv4). False with `why` when malformed; `out` may be null.
bool parse_udp_endpoint(const std::string& text, sockaddr_in* out, std::string* why);

class UdpLink {
 public:
  // `pinned_peer` ("a.b.c.d:port", server only; empty: learn it from the
  // autopilot's valid frames through set_peer).
  UdpLink(bool server, std::string local, std::string remote, std::string pinned_peer = "");
  ~UdpLink();
  UdpLink(const UdpLink&) = delete;
  UdpLink& operator=(const UdpLink&) = delete;

  // Throws std::runtime_error naming the address when the socket cannot be bound.
  void open();
  int fd() const { return fd_; }
  uint16_t local_port() const;
  // One datagram and its sender (`from` may be null), or false when none is
  // waiting. A pinned server skips (and counts) datagrams from other senders.
  bool receive(std::vector<uint8_t>* datagram, sockaddr_in* from = nullptr);
  // Server: reply to `peer` from now on (counted when it changes). Ignored by
  // a client, whose peer is its configured remote, and by a pinned server.
  void set_peer(const sockaddr_in& peer);
  int64_t peer_changes() const { return peer_changes_; }
  // False when there is nobody to send to yet (server before the first
  // datagram) or the send failed (counted).
  bool send(const uint8_t* data, size_t size);
  bool has_peer() const { return have_peer_; }
  std::string peer() const;
  bool pinned() const { return !pinned_peer_.empty(); }
  int64_t datagrams_in() const { return datagrams_in_; }
  int64_t foreign_datagrams() const { return foreign_datagrams_; }  // pinned: from another sender
  int64_t datagrams_out() const { return datagrams_out_; }
  int64_t send_failures() const { return send_failures_; }
  const std::string& last_error() const { return last_error_; }

 private:
  bool server_;
  std::string local_;
  std::string remote_;
  std::string pinned_peer_;
  int fd_ = -1;
  sockaddr_in peer_{};
  bool have_peer_ = false;
  int64_t datagrams_in_ = 0;
  int64_t datagrams_out_ = 0;
  int64_t send_failures_ = 0;
  int64_t peer_changes_ = 0;
  int64_t foreign_datagrams_ = 0;
  std::string last_error_;
};

}  // namespace nadir::mavlink_bridge
