#include <gtest/gtest.h>
#include <sys/socket.h>
#include <unistd.h>

#include <vector>

#include "common/udp_drops.h"
#include "tests/common/test_support.h"

namespace nadir {
namespace {

// A UDP socket on loopback that is never read while datagrams pour in: the
// kernel drops what does not fit, and every datagram is either still queued
// or counted as dropped.
TEST(UdpDrops, CountsExactlyWhatTheKernelDroppedForAFullReceiveBuffer) {
  const int before = static_cast<int>(own_udp_receive_drops());
  ASSERT_GE(before, 0) << "/proc/self/net/udp unreadable";
  const int sent = 300;
  int port = 0;
  const int receiver = testing::overflowed_udp_socket(sent, &port);
  const int dropped = static_cast<int>(own_udp_receive_drops()) - before;
  int queued = 0;
  std::vector<char> buffer(2000);
  while (recv(receiver, buffer.data(), buffer.size(), MSG_DONTWAIT) > 0) ++queued;
  EXPECT_GT(dropped, 0);
  EXPECT_EQ(queued + dropped, sent);
  // Closed sockets no longer count: the figure is this process's, now.
  close(receiver);
  EXPECT_EQ(own_udp_receive_drops(), before);
}

// Only the sockets on the asked port count: a process's other UDP sockets (a
// camera's stream, a MAVLink link) are not its bus.
TEST(UdpDrops, CountsOnlyTheSocketsOnTheGivenPort) {
  int bus_port = 0, other_port = 0;
  const int bus = testing::overflowed_udp_socket(300, &bus_port);
  const int bus_drops = static_cast<int>(own_udp_receive_drops(bus_port));
  ASSERT_GT(bus_drops, 0);
  const int other = testing::overflowed_udp_socket(300, &other_port);
  ASSERT_NE(other_port, bus_port);
  const int other_drops = static_cast<int>(own_udp_receive_drops(other_port));
  EXPECT_GT(other_drops, 0);
  EXPECT_EQ(own_udp_receive_drops(bus_port), bus_drops);  // the other socket's drops are not the bus's
  EXPECT_GE(own_udp_receive_drops(), bus_drops + other_drops);
  close(bus);
  close(other);
}

}  // namespace
}  // namespace nadir
