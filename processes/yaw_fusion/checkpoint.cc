#include "processes/yaw_fusion/checkpoint.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <vector>

#include "common/message_guard.h"

namespace nadir {

std::optional<pose_t> PoseCheckpoint::load(std::string* problem) const {
  std::ifstream in(path_, std::ios::binary);
  if (!in) return std::nullopt;
  const std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  pose_t pose;
  std::string reason;
  if (!decode_message(bytes.data(), bytes.size(), &pose, &reason)) {
    *problem = path_ + ": not a POSE checkpoint (" + reason + "), starting afresh";
    return std::nullopt;
  }
  return pose;
}

void PoseCheckpoint::save(const pose_t& pose) {
  std::vector<uint8_t> bytes(static_cast<size_t>(pose.getEncodedSize()));
  pose.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  const std::string tmp = path_ + ".tmp";
  FILE* f = std::fopen(tmp.c_str(), "wb");
  bool ok = f != nullptr && std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size();
  if (f != nullptr) ok = std::fclose(f) == 0 && ok;
  ok = ok && std::rename(tmp.c_str(), path_.c_str()) == 0;
  if (!ok) {
    ++save_errors_;
    last_error_ = path_ + ": checkpoint not written: " + std::strerror(errno);
    return;
  }
  ++saves_;
}

}  // namespace nadir
