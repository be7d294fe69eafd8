#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <vector>

#include "common/udp_drops.h"

namespace nadir {
namespace {

// A UDP socket on loopback that is never read while datagrams pour in: the
// kernel drops what does not fit, and every datagram is either still queued
// or counted as dropped.
TEST(UdpDrops, CountsExactlyWhatTheKernelDroppedForAFullReceiveBuffer) {
  const int before = static_cast<int>(own_udp_receive_drops());
  ASSERT_GE(before, 0) << "/proc/self/net/udp unreadable";
  const int receiver = socket(AF_INET, SOCK_DGRAM, 0);
  ASSERT_GE(receiver, 0);
  const int small = 4096;
  ASSERT_EQ(setsockopt(receiver, SOL_SOCKET, SO_RCVBUF, &small, sizeof(small)), 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ASSERT_EQ(bind(receiver, reinterpret_cast<sockaddr*>(&address), sizeof(address)), 0);
  socklen_t length = sizeof(address);
  ASSERT_EQ(getsockname(receiver, reinterpret_cast<sockaddr*>(&address), &length), 0);

  const int sender = socket(AF_INET, SOCK_DGRAM, 0);
  ASSERT_GE(sender, 0);
  const std::vector<char> payload(1000, 'x');
  const int sent = 300;
  for (int i = 0; i < sent; ++i) {
    ASSERT_EQ(sendto(sender, payload.data(), payload.size(), 0, reinterpret_cast<sockaddr*>(&address),
                     sizeof(address)),
              static_cast<ssize_t>(payload.size()));
  }
  const int dropped = static_cast<int>(own_udp_receive_drops()) - before;
  int queued = 0;
  std::vector<char> buffer(2000);
  while (recv(receiver, buffer.data(), buffer.size(), MSG_DONTWAIT) > 0) ++queued;
  EXPECT_GT(dropped, 0);
  EXPECT_EQ(queued + dropped, sent);
  // Closed sockets no longer count: the figure is this process's, now.
  close(receiver);
  close(sender);
  EXPECT_EQ(own_udp_receive_drops(), before);
}

}  // namespace
}  // namespace nadir
