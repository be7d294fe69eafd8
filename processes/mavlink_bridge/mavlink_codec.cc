#include "processes/mavlink_bridge/mavlink_codec.h"

#include <map>

namespace nadir::mavlink {

const MessageInfo* find_message(uint32_t id) {
  static const std::map<uint32_t, MessageInfo> table = [] {
    std::map<uint32_t, MessageInfo> t;
    for_each_message_type([&](auto m) { t[decltype(m)::kId] = message_info<decltype(m)>(); });
    return t;
  }();
  const auto it = table.find(id);
  return it == table.end() ? nullptr : &it->second;
}

}  // namespace nadir::mavlink
