#pragma once
// Helpers shared by tests: temp folders, file digests, network-namespace check.

#include <cstdint>
#include <string>
#include <vector>

namespace nadir::testing {

// A fresh folder under the build tree's test_tmp/, removed when destroyed.
class TempDir {
 public:
  explicit TempDir(const std::string& tag);
  ~TempDir();
  const std::string& path() const { return path_; }
  std::string file(const std::string& name) const { return path_ + "/" + name; }

 private:
  std::string path_;
};

std::vector<uint8_t> read_file_bytes(const std::string& path);
void write_file_bytes(const std::string& path, const std::vector<uint8_t>& bytes);
// FNV-1a 64 of a file's bytes, as hex.
std::string file_digest(const std::string& path);
// True inside the private network namespace test.sh creates (NADIR_IN_NETNS=1).
bool in_private_netns();
// A UDP socket bound to loopback with a 4 KB receive buffer, sent `datagrams`
// datagrams of 1000 bytes and never read: the kernel dropped what did not
// fit. Returns the socket (the caller closes it) and its port in *port;
// throws std::runtime_error when a socket call fails.
int overflowed_udp_socket(int datagrams, int* port);

}  // namespace nadir::testing
