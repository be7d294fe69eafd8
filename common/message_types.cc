#include "common/message_types.h"

#include <cstdio>

#include "nadir/altimeter_t.hpp"
#include "nadir/config_t.hpp"
#include "nadir/ground_points_t.hpp"
#include "nadir/ground_truth_t.hpp"
#include "nadir/image_t.hpp"
#include "nadir/ins_t.hpp"
#include "nadir/map_fix_t.hpp"
#include "nadir/pose_t.hpp"
#include "nadir/status_t.hpp"
#include "nadir/tracks_t.hpp"
#include "nadir/trigger_t.hpp"
#include "nadir/vo_delta_t.hpp"

namespace nadir {
namespace {

template <class Msg>
bool is(uint64_t hash) {
  return static_cast<uint64_t>(Msg::getHash()) == hash;
}

}  // namespace

std::string message_type_name(const uint8_t* data, size_t size) {
  if (size < 8) return "unknown (shorter than a fingerprint)";
  uint64_t hash = 0;
  for (int i = 0; i < 8; ++i) hash = (hash << 8) | data[i];
  if (is<image_t>(hash)) return "nadir.image_t";
  if (is<trigger_t>(hash)) return "nadir.trigger_t";
  if (is<ins_t>(hash)) return "nadir.ins_t";
  if (is<altimeter_t>(hash)) return "nadir.altimeter_t";
  if (is<tracks_t>(hash)) return "nadir.tracks_t";
  if (is<vo_delta_t>(hash)) return "nadir.vo_delta_t";
  if (is<ground_points_t>(hash)) return "nadir.ground_points_t";
  if (is<pose_t>(hash)) return "nadir.pose_t";
  if (is<map_fix_t>(hash)) return "nadir.map_fix_t";
  if (is<ground_truth_t>(hash)) return "nadir.ground_truth_t";
  if (is<status_t>(hash)) return "nadir.status_t";
  if (is<config_t>(hash)) return "nadir.config_t";
  char text[48];
  std::snprintf(text, sizeof(text), "unknown (fingerprint 0x%016llx)", static_cast<unsigned long long>(hash));
  return text;
}

}  // namespace nadir
