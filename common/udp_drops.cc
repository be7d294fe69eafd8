#include "common/udp_drops.h"

#include <dirent.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <set>
#include <sstream>
#include <string>

namespace nadir {
namespace {

// Inodes of the sockets among this process's open file descriptors
// ("/proc/self/fd/N -> socket:[INODE]").
bool own_socket_inodes(std::set<uint64_t>* inodes) {
  DIR* dir = opendir("/proc/self/fd");
  if (dir == nullptr) return false;
  while (const dirent* entry = readdir(dir)) {
    const std::string path = std::string("/proc/self/fd/") + entry->d_name;
    char target[128];
    const ssize_t n = readlink(path.c_str(), target, sizeof(target) - 1);
    if (n <= 0) continue;
    target[n] = '\0';
    uint64_t inode = 0;
    if (std::sscanf(target, "socket:[%lu]", &inode) == 1) inodes->insert(inode);
  }
  closedir(dir);
  return true;
}

// Lines of /proc/net/udp after the header: "sl local rem st tx:rx tr:when
// retrnsmt uid timeout inode ref pointer drops", local as hex ADDRESS:PORT.
// Returns the drops of the sockets in `inodes` (bound to local_port, when
// not 0).
int64_t drops_in_table(const std::string& table, const std::set<uint64_t>& inodes, int local_port) {
  std::istringstream lines(table);
  std::string line;
  std::getline(lines, line);  // header
  int64_t drops = 0;
  while (std::getline(lines, line)) {
    std::istringstream fields(line);
    std::string field[13];
    int count = 0;
    while (count < 13 && fields >> field[count]) ++count;
    if (count < 13) continue;
    try {
      const size_t colon = field[1].rfind(':');
      if (local_port != 0 && (colon == std::string::npos || std::stoi(field[1].substr(colon + 1), nullptr, 16) != local_port))
        continue;
      if (inodes.count(std::stoull(field[9])) != 0) drops += std::stoll(field[12]);
    } catch (const std::exception&) {
      continue;  // a line of another shape: not ours to judge
    }
  }
  return drops;
}

std::string read_text(const char* path, bool* ok) {
  std::ifstream in(path);
  *ok = static_cast<bool>(in);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace

int64_t own_udp_receive_drops(int local_port) {
  std::set<uint64_t> inodes;
  if (!own_socket_inodes(&inodes)) return -1;
  bool v4 = false;
  bool v6 = false;
  const std::string udp = read_text("/proc/self/net/udp", &v4);
  const std::string udp6 = read_text("/proc/self/net/udp6", &v6);
  if (!v4 && !v6) return -1;
  return drops_in_table(udp, inodes, local_port) + drops_in_table(udp6, inodes, local_port);
}

}  // namespace nadir
