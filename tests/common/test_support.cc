#include "tests/common/test_support.h"

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

}  // namespace nadir::testing
