#include "processes/yaw_fusion/checkpoint.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <vector>

#include "common/message_guard.h"

namespace nadir {

yaw_fusion_checkpoint_t checkpoint_without_bias(const pose_t& pose) {
  yaw_fusion_checkpoint_t checkpoint{};
  checkpoint.pose = pose;
  checkpoint.has_heading_bias = false;
  return checkpoint;
}

std::optional<yaw_fusion_checkpoint_t> PoseCheckpoint::load(std::string* problem) const {
  std::ifstream in(path_, std::ios::binary);
  if (!in) return std::nullopt;
  const std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  yaw_fusion_checkpoint_t checkpoint;
  std::string reason;
  if (decode_message(bytes.data(), bytes.size(), &checkpoint, &reason)) return checkpoint;
  pose_t pose;
  std::string pose_reason;
  if (decode_message(bytes.data(), bytes.size(), &pose, &pose_reason)) return checkpoint_without_bias(pose);
  *problem = path_ + ": not a yaw fusion checkpoint (" + reason + "), starting afresh";
  return std::nullopt;
}

void PoseCheckpoint::save(const yaw_fusion_checkpoint_t& checkpoint) {
  const std::vector<uint8_t> bytes = encode_message(checkpoint);
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
