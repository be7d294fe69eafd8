#include "tests/common/test_support.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <sstream>
#include <stdexcept>

namespace nadir::testing {
namespace fs = std::filesystem;

TempDir::TempDir(const std::string& tag) {
  const fs::path base = fs::path(NADIR_BINARY_DIR) / "test_tmp";
  fs::create_directories(base);
  path_ = (base / (tag + "-" + std::to_string(getpid()) + "-" + std::to_string(std::random_device{}()))).string();
  fs::create_directories(path_);
}

TempDir::~TempDir() {
  std::error_code ec;
  fs::remove_all(path_, ec);
}

std::vector<uint8_t> read_file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + path);
  return std::vector<uint8_t>(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

void write_file_bytes(const std::string& path, const std::vector<uint8_t>& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  if (!out) throw std::runtime_error("cannot write " + path);
}

std::string file_digest(const std::string& path) {
  uint64_t hash = 1469598103934665603ull;
  for (uint8_t b : read_file_bytes(path)) {
    hash ^= b;
    hash *= 1099511628211ull;
  }
  char text[17];
  std::snprintf(text, sizeof(text), "%016llx", static_cast<unsigned long long>(hash));
  return text;
}

bool in_private_netns() {
  const char* env = std::getenv("NADIR_IN_NETNS");
  return env != nullptr && std::string(env) == "1";
}

int overflowed_udp_socket(int datagrams, int* port) {
  const int receiver = socket(AF_INET, SOCK_DGRAM, 0);
  const int small = 4096;
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t length = sizeof(address);
  if (receiver < 0 || setsockopt(receiver, SOL_SOCKET, SO_RCVBUF, &small, sizeof(small)) != 0 ||
      bind(receiver, reinterpret_cast<sockaddr*>(&address), sizeof(address)) != 0 ||
      getsockname(receiver, reinterpret_cast<sockaddr*>(&address), &length) != 0) {
    throw std::runtime_error("overflowed_udp_socket: could not bind a UDP socket on loopback");
  }
  *port = ntohs(address.sin_port);
  const int sender = socket(AF_INET, SOCK_DGRAM, 0);
  if (sender < 0) throw std::runtime_error("overflowed_udp_socket: no sending socket");
  const std::vector<char> payload(1000, 'x');
  for (int i = 0; i < datagrams; ++i) {
    if (sendto(sender, payload.data(), payload.size(), 0, reinterpret_cast<sockaddr*>(&address), sizeof(address)) !=
        static_cast<ssize_t>(payload.size())) {
      close(sender);
      throw std::runtime_error("overflowed_udp_socket: sendto failed");
    }
  }
  close(sender);
  return receiver;
}

}  // namespace nadir::testing
