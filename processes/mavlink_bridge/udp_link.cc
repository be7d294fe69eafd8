#include "processes/mavlink_bridge/udp_link.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace nadir::mavlink_bridge {

bool parse_udp_endpoint(const std::string& text, sockaddr_in* out, std::string* why) {
  const size_t colon = text.rfind(':');
  if (colon == std::string::npos) {
    *why = "= '" + text + "' must be ADDRESS:PORT, e.g. 127.0.0.1:14540";
    return false;
  }
  const std::string host = text.substr(0, colon);
  const std::string port_text = text.substr(colon + 1);
  char* end = nullptr;
  const long port = std::strtol(port_text.c_str(), &end, 10);
  if (port_text.empty() || *end != '\0' || port < 0 || port > 65535) {
    *why = "= '" + text + "': port must be a number in [0, 65535]";
    return false;
  }
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(static_cast<uint16_t>(port));
  if (inet_pton(AF_INET, host.c_str(), &addr.sin_addr) != 1) {
    *why = "= '" + text + "': '" + host + "' is not a numeric IPv4 address";
    return false;
  }
  if (out) *out = addr;
  return true;
}

UdpLink::UdpLink(bool server, std::string local, std::string remote, std::string pinned_peer)
    : server_(server), local_(std::move(local)), remote_(std::move(remote)), pinned_peer_(std::move(pinned_peer)) {}

UdpLink::~UdpLink() {
  if (fd_ >= 0) ::close(fd_);
}

void UdpLink::open() {
  std::string why;
  sockaddr_in local{};
  if (!parse_udp_endpoint(local_, &local, &why)) throw std::runtime_error("UDP local address " + why);
  if (!server_) {
    if (!parse_udp_endpoint(remote_, &peer_, &why)) throw std::runtime_error("UDP remote address " + why);
    have_peer_ = true;
  } else if (pinned()) {
    if (!parse_udp_endpoint(pinned_peer_, &peer_, &why)) throw std::runtime_error("UDP autopilot address " + why);
    have_peer_ = true;
  }
  fd_ = ::socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (fd_ < 0) throw std::runtime_error(std::string("UDP socket: ") + std::strerror(errno));
  if (::bind(fd_, reinterpret_cast<const sockaddr*>(&local), sizeof local) != 0) {
    const std::string error = std::strerror(errno);
    ::close(fd_);
    fd_ = -1;
    throw std::runtime_error("UDP bind " + local_ + ": " + error);
  }
}

uint16_t UdpLink::local_port() const {
  sockaddr_in addr{};
  socklen_t len = sizeof addr;
  if (fd_ < 0 || ::getsockname(fd_, reinterpret_cast<sockaddr*>(&addr), &len) != 0) return 0;
  return ntohs(addr.sin_port);
}

bool UdpLink::receive(std::vector<uint8_t>* datagram, sockaddr_in* sender) {
  for (;;) {
    datagram->resize(65536);
    sockaddr_in from{};
    socklen_t len = sizeof from;
    const ssize_t got =
        ::recvfrom(fd_, datagram->data(), datagram->size(), 0, reinterpret_cast<sockaddr*>(&from), &len);
    if (got < 0) {
      datagram->clear();
      return false;
    }
    if (server_ && pinned() && (from.sin_addr.s_addr != peer_.sin_addr.s_addr || from.sin_port != peer_.sin_port)) {
      ++foreign_datagrams_;
      continue;
    }
    datagram->resize(static_cast<size_t>(got));
    ++datagrams_in_;
    if (sender) *sender = from;
    return true;
  }
}

void UdpLink::set_peer(const sockaddr_in& peer) {
  if (!server_ || pinned()) return;
  const bool same = have_peer_ && peer.sin_addr.s_addr == peer_.sin_addr.s_addr && peer.sin_port == peer_.sin_port;
  if (same) return;
  if (have_peer_) ++peer_changes_;
  peer_ = peer;
  have_peer_ = true;
}

bool UdpLink::send(const uint8_t* data, size_t size) {
  if (!have_peer_) return false;
  const ssize_t sent = ::sendto(fd_, data, size, 0, reinterpret_cast<const sockaddr*>(&peer_), sizeof peer_);
  if (sent != static_cast<ssize_t>(size)) {
    ++send_failures_;
    last_error_ = "UDP send to " + peer() + ": " + std::strerror(errno);
    return false;
  }
  ++datagrams_out_;
  return true;
}

std::string UdpLink::peer() const {
  if (!have_peer_) return "(none yet)";
  char text[INET_ADDRSTRLEN] = {};
  inet_ntop(AF_INET, &peer_.sin_addr, text, sizeof text);
  return std::string(text) + ":" + std::to_string(ntohs(peer_.sin_port));
}

}  // namespace nadir::mavlink_bridge
