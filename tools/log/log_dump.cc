#include "tools/log/log_dump.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <functional>
#include <memory>
#include <set>
#include <stdexcept>
#include <variant>

#include "common/json_writer.h"
#include "common/log_file.h"
#include "common/message_guard.h"
#include "common/message_types.h"
#include "nadir/altimeter_t.hpp"
#include "nadir/ground_points_t.hpp"
#include "nadir/ground_truth_t.hpp"
#include "nadir/ins_t.hpp"
#include "nadir/pose_t.hpp"
#include "nadir/tracks_t.hpp"
#include "nadir/vo_delta_t.hpp"

namespace nadir {
namespace {

using Value = std::variant<int64_t, double, std::string>;
using Row = std::vector<Value>;

// Shortest text that reads back to the same double; "nan"/"inf" in CSV, null in JSON.
std::string number_text(double v) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof(buf), v);
  return std::string(buf, r.ptr);
}

std::string csv_text(const Value& v) {
  if (const auto* i = std::get_if<int64_t>(&v)) return std::to_string(*i);
  if (const auto* d = std::get_if<double>(&v)) return number_text(*d);
  const std::string& s = std::get<std::string>(v);
  if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
  std::string quoted = "\"";
  for (char c : s) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

std::string json_text(const Value& v) {
  if (const auto* d = std::get_if<double>(&v)) return std::isfinite(*d) ? number_text(*d) : "null";
  if (const auto* i = std::get_if<int64_t>(&v)) return std::to_string(*i);
  return "\"" + json_escape(std::get<std::string>(v)) + "\"";
}

// One supported type: its fingerprint, its columns, and the rows of one message
// (false when the message does not decode).
struct DumpType {
  std::string name;
  int64_t hash;
  std::vector<std::string> columns;
  std::function<bool(const uint8_t*, size_t, std::vector<Row>*, std::string*)> rows;
};

template <class Msg>
DumpType make_type(const std::string& name, std::vector<std::string> columns,
                   std::function<void(const Msg&, std::vector<Row>*)> to_rows) {
  return DumpType{name, Msg::getHash(), std::move(columns),
                  [to_rows](const uint8_t* data, size_t size, std::vector<Row>* rows, std::string* reason) {
                    Msg msg{};
                    if (!decode_message(data, size, &msg, reason)) return false;
                    to_rows(msg, rows);
                    return true;
                  }};
}

const std::vector<DumpType>& dump_types() {
  static const std::vector<DumpType> types = {
      make_type<tracks_t>(
          "nadir.tracks_t",
          {"utime", "prev_utime", "frame_counter", "flags", "track_id", "age", "prev_px_x", "prev_px_y", "curr_px_x",
           "curr_px_y", "prev_norm_x", "prev_norm_y", "curr_norm_x", "curr_norm_y"},
          [](const tracks_t& m, std::vector<Row>* rows) {
            for (int i = 0; i < m.num_tracks; ++i) {
              rows->push_back({m.utime, m.prev_utime, m.frame_counter, int64_t{m.flags}, m.track_id[i],
                               int64_t{m.age[i]}, double{m.prev_px[i][0]}, double{m.prev_px[i][1]},
                               double{m.curr_px[i][0]}, double{m.curr_px[i][1]}, m.prev_norm[i][0], m.prev_norm[i][1],
                               m.curr_norm[i][0], m.curr_norm[i][1]});
            }
          }),
      make_type<ground_points_t>(
          "nadir.ground_points_t", {"utime", "track_id", "x_m", "y_m", "z_m", "depth_sigma_m"},
          [](const ground_points_t& m, std::vector<Row>* rows) {
            const size_t n = std::min({static_cast<size_t>(std::max(0, m.num_points)), m.track_id.size(),
                                       m.position_m.size(), m.depth_sigma_m.size()});
            for (size_t i = 0; i < n; ++i) {
              rows->push_back({m.utime, m.track_id[i], double{m.position_m[i][0]}, double{m.position_m[i][1]},
                               double{m.position_m[i][2]}, double{m.depth_sigma_m[i]}});
            }
          }),
      make_type<vo_delta_t>(
          "nadir.vo_delta_t",
          {"utime", "prev_utime", "dx", "dy", "dz", "dyaw", "ground_roll", "ground_pitch", "var_dx", "var_dy", "var_dz",
           "var_dyaw", "var_ground_roll", "var_ground_pitch", "altitude_m", "inliers", "outliers", "residual_rms_px",
           "iterations", "quality", "variant"},
          [](const vo_delta_t& m, std::vector<Row>* rows) {
            rows->push_back({m.utime, m.prev_utime, m.dx, m.dy, m.dz, m.dyaw, m.ground_roll, m.ground_pitch,
                             m.covariance[0][0], m.covariance[1][1], m.covariance[2][2], m.covariance[3][3],
                             m.covariance[4][4], m.covariance[5][5], m.altitude_m, int64_t{m.inliers},
                             int64_t{m.outliers}, m.residual_rms_px, int64_t{m.iterations}, int64_t{m.quality},
                             m.variant});
          }),
      make_type<ins_t>(
          "nadir.ins_t",
          {"utime", "device_utime", "roll", "pitch", "yaw", "latitude_deg", "longitude_deg", "height_m", "velocity_n",
           "velocity_e", "velocity_d", "ins_status", "flags"},
          [](const ins_t& m, std::vector<Row>* rows) {
            rows->push_back({m.utime, m.device_utime, m.roll, m.pitch, m.yaw, m.latitude_deg, m.longitude_deg,
                             m.height_m, m.velocity_ned[0], m.velocity_ned[1], m.velocity_ned[2],
                             int64_t{m.ins_status}, int64_t{m.flags}});
          }),
      make_type<altimeter_t>(
          "nadir.altimeter_t", {"utime", "range_m", "beam_x", "beam_y", "beam_z", "signal_quality", "validity"},
          [](const altimeter_t& m, std::vector<Row>* rows) {
            rows->push_back({m.utime, m.range_m, m.beam_body[0], m.beam_body[1], m.beam_body[2],
                             double{m.signal_quality}, int64_t{m.validity}});
          }),
      make_type<pose_t>(
          "nadir.pose_t",
          {"utime", "north", "east", "down", "velocity_n", "velocity_e", "velocity_d", "roll", "pitch", "yaw",
           "height_agl_m", "var_north", "var_east", "var_down", "yaw_variance", "protection_level_h",
           "flags", "frames"},
          [](const pose_t& m, std::vector<Row>* rows) {
            rows->push_back({m.utime, m.position_ned[0], m.position_ned[1], m.position_ned[2], m.velocity_ned[0],
                             m.velocity_ned[1], m.velocity_ned[2], m.roll, m.pitch, m.yaw, m.height_agl_m,
                             m.position_covariance[0][0], m.position_covariance[1][1], m.position_covariance[2][2],
                             m.yaw_variance, m.horizontal_protection_level_m, int64_t{m.flags}, m.frames});
          }),
      make_type<ground_truth_t>(
          "nadir.ground_truth_t",
          {"utime", "kind", "north", "east", "down", "velocity_n", "velocity_e", "velocity_d", "roll", "pitch", "yaw",
           "height_agl_m", "terrain_height_m"},
          [](const ground_truth_t& m, std::vector<Row>* rows) {
            rows->push_back({m.utime, int64_t{m.kind}, m.position_ned[0], m.position_ned[1], m.position_ned[2],
                             m.velocity_ned[0], m.velocity_ned[1], m.velocity_ned[2], m.roll, m.pitch, m.yaw,
                             m.height_agl_m, m.terrain_height_m});
          }),
  };
  return types;
}

const DumpType* type_of(const uint8_t* data, size_t size) {
  if (size < 8) return nullptr;
  uint64_t hash = 0;
  for (int i = 0; i < 8; ++i) hash = (hash << 8) | data[i];
  for (const DumpType& t : dump_types()) {
    if (static_cast<uint64_t>(t.hash) == hash) return &t;
  }
  return nullptr;
}

void write_row(const DumpType& type, const Row& row, DumpFormat format, std::ostream& out) {
  if (format == DumpFormat::kCsv) {
    for (size_t i = 0; i < row.size(); ++i) out << (i ? "," : "") << csv_text(row[i]);
    out << "\n";
    return;
  }
  out << "{";
  for (size_t i = 0; i < row.size(); ++i) {
    out << (i ? "," : "") << "\"" << type.columns[i] << "\":" << json_text(row[i]);
  }
  out << "}\n";
}

std::string joined(const std::set<std::string>& names) {
  std::string s;
  for (const std::string& n : names) s += (s.empty() ? "" : ", ") + n;
  return s.empty() ? "none" : s;
}

}  // namespace

std::vector<std::string> dumpable_types() {
  std::vector<std::string> names;
  for (const DumpType& t : dump_types()) names.push_back(t.name);
  return names;
}

DumpStats dump_channel(const std::string& path, const std::string& channel, DumpFormat format, std::ostream& out) {
  std::unique_ptr<LogReader> opened;
  try {
    opened = std::make_unique<LogReader>(path);
  } catch (const std::exception& e) {
    throw std::runtime_error(std::string(e.what()) + " (dumping channel " + channel + ")");
  }
  LogReader& reader = *opened;
  LogEvent e;
  DumpStats stats;
  const DumpType* type = nullptr;
  std::set<std::string> channels_present;
  std::string unsupported;  // type name of the channel's first message when not dumpable
  int64_t on_channel = 0;
  std::vector<Row> rows;
  while (reader.next(&e)) {
    channels_present.insert(e.channel);
    if (e.channel != channel) continue;
    ++on_channel;
    const DumpType* t = type_of(e.data, e.size);
    if (t == nullptr) {
      if (unsupported.empty()) unsupported = message_type_name(e.data, e.size);
      ++stats.undecodable;
      continue;
    }
    if (type != nullptr && t != type) {  // a second type on one channel: not one table
      ++stats.undecodable;
      if (stats.first_decode_error.empty()) stats.first_decode_error = "message of type " + t->name + " among " + type->name;
      continue;
    }
    rows.clear();
    std::string reason;
    if (!t->rows(e.data, e.size, &rows, &reason)) {
      ++stats.undecodable;
      if (stats.first_decode_error.empty()) stats.first_decode_error = "byte " + std::to_string(e.offset) + ": " + reason;
      continue;
    }
    if (type == nullptr) {
      type = t;
      stats.type = t->name;
      if (format == DumpFormat::kCsv) {
        for (size_t i = 0; i < t->columns.size(); ++i) out << (i ? "," : "") << t->columns[i];
        out << "\n";
      }
    }
    ++stats.messages;
    for (const Row& row : rows) write_row(*t, row, format, out);
    stats.rows += static_cast<int64_t>(rows.size());
  }
  stats.corrupt_records = reader.corrupt_records();
  stats.truncated = reader.truncated();
  stats.damage_report = reader.damage_report();
  if (type != nullptr) return stats;
  const std::string where = path + ": channel " + channel + ": ";
  if (on_channel == 0) throw std::runtime_error(where + "no messages (channels in the log: " + joined(channels_present) + ")");
  if (!unsupported.empty()) {
    std::set<std::string> supported;
    for (const std::string& n : dumpable_types()) supported.insert(n);
    throw std::runtime_error(where + "carries " + unsupported + ", which dump does not support (supported: " +
                             joined(supported) + ")");
  }
  throw std::runtime_error(where + "none of its " + std::to_string(on_channel) +
                           " message(s) decodes (first: " + stats.first_decode_error + ")");
}

}  // namespace nadir
