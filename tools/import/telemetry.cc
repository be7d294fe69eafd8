#include "tools/import/telemetry.h"

#include <cmath>
#include <ctime>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <stdexcept>

namespace nadir::import {
namespace {

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path + ": cannot open");
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::vector<std::string> split_lines(const std::string& text) {
  std::vector<std::string> lines;
  std::string line;
  std::istringstream in(text);
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    lines.push_back(line);
  }
  if (!lines.empty() && lines.front().rfind("\xEF\xBB\xBF", 0) == 0) lines.front().erase(0, 3);  // UTF-8 BOM
  return lines;
}

class BadRecord : public std::runtime_error {
 public:
  BadRecord(int line, const std::string& what) : std::runtime_error(what), line(line) {}
  int line;
};

// Handles one bad record: throws naming FILE:LINE, or counts it.
void bad(Telemetry* t, bool skip_bad, int line, const std::string& what) {
  const std::string where = t->path + ":" + std::to_string(line);
  if (!skip_bad) throw std::runtime_error(where + ": " + what);
  t->skipped.push_back({where, what});
}

// SRT "HH:MM:SS,mmm" -> seconds.
bool parse_srt_clock(const std::string& text, double* s) {
  static const std::regex re(R"((\d+):(\d{2}):(\d{2})[,.](\d{1,3}))");
  std::smatch m;
  if (!std::regex_match(text, m, re)) return false;
  *s = std::stoi(m[1]) * 3600.0 + std::stoi(m[2]) * 60.0 + std::stoi(m[3]) + std::stoi(m[4]) * std::pow(10.0, -static_cast<double>(m[4].length()));
  return true;
}

// SRT fields "key: value" inside brackets (and "FrameCnt: N, DiffTime: Dms").
std::map<std::string, std::string> srt_fields(const std::string& text) {
  std::map<std::string, std::string> fields;
  static const std::regex re(R"(([A-Za-z_]+)\s*:\s*([-+0-9.eE]+))");
  for (auto it = std::sregex_iterator(text.begin(), text.end(), re); it != std::sregex_iterator(); ++it) {
    fields[(*it)[1]] = (*it)[2];
  }
  return fields;
}

void parse_srt_block(const std::vector<std::string>& lines, size_t begin, size_t end, TelemetryRecord* r) {
  const int first = static_cast<int>(begin) + 1;
  double index = 0;
  if (!parse_number(lines[begin], &index)) throw BadRecord(first, "subtitle index expected, got '" + lines[begin] + "'");
  if (begin + 1 >= end) throw BadRecord(first, "subtitle block without a time line");
  static const std::regex arrow(R"(\s*(\S+)\s*-->\s*(\S+)\s*)");
  std::smatch m;
  double stop = 0;
  if (!std::regex_match(lines[begin + 1], m, arrow) || !parse_srt_clock(m[1], &r->time_s) ||
      !parse_srt_clock(m[2], &stop)) {
    throw BadRecord(first + 1, "time line 'HH:MM:SS,mmm --> HH:MM:SS,mmm' expected, got '" + lines[begin + 1] + "'");
  }
  std::string text;
  for (size_t i = begin + 2; i < end; ++i) {
    text += lines[i] + "\n";
    static const std::regex date(R"((\d{4}-\d{2}-\d{2} \d{2}:\d{2}:\d{2}(\.\d+)?))");
    std::smatch d;
    if (r->absolute_time_s < 0 && std::regex_search(lines[i], d, date)) parse_date_time(d[1], &r->absolute_time_s);
  }
  // The date line's own "HH:MM:SS" would look like fields; take them out first.
  static const std::regex date_any(R"(\d{4}-\d{2}-\d{2} \d{2}:\d{2}:\d{2}(\.\d+)?)");
  const std::map<std::string, std::string> f = srt_fields(std::regex_replace(text, date_any, ""));
  // The line of the block that holds `key:` (for errors).
  auto line_of = [&](const std::string& key) {
    for (size_t i = begin + 2; i < end; ++i) {
      if (lines[i].find(key + ":") != std::string::npos || lines[i].find(key + " :") != std::string::npos) {
        return static_cast<int>(i) + 1;
      }
    }
    return first;
  };
  auto number = [&](const std::string& key, double* v) {
    const auto it = f.find(key);
    if (it == f.end()) return false;
    if (!parse_number(it->second, v)) {
      throw BadRecord(line_of(key), "field '" + key + "' is not a number: '" + it->second + "'");
    }
    return true;
  };
  const std::string block = "subtitle block (lines " + std::to_string(first) + "-" + std::to_string(end) + ")";
  auto required = [&](const std::string& key, double* v) {
    if (!number(key, v)) throw BadRecord(first, block + ": field '" + key + "' is missing");
  };
  double frame = 0;
  if (number("FrameCnt", &frame)) r->frame = static_cast<int64_t>(frame);
  required("latitude", &r->lat_deg);
  required("longitude", &r->lon_deg);
  required("rel_alt", &r->height_m);
  r->has_height = true;
  r->has_alt = number("abs_alt", &r->alt_m);
  required("gb_yaw", &r->gimbal_yaw_deg);
  required("gb_pitch", &r->gimbal_pitch_deg);
  required("gb_roll", &r->gimbal_roll_deg);
  r->has_gimbal = true;
  const int body = number("flight_yaw", &r->yaw_deg) + number("flight_pitch", &r->pitch_deg) + number("flight_roll", &r->roll_deg);
  if (body != 0 && body != 3) throw BadRecord(first, block + ": flight_yaw/flight_pitch/flight_roll must come together");
  r->has_body = body == 3;
  r->has_range = number("range", &r->range_m);
  if (std::abs(r->lat_deg) > 90.0 || std::abs(r->lon_deg) > 180.0) throw BadRecord(line_of("latitude"), "latitude/longitude out of range");
}

}  // namespace

std::string trim(const std::string& s) {
  const size_t a = s.find_first_not_of(" \t\r\n");
  if (a == std::string::npos) return "";
  return s.substr(a, s.find_last_not_of(" \t\r\n") - a + 1);
}

bool parse_number(const std::string& text, double* value) {
  const std::string t = trim(text);
  if (t.empty()) return false;
  char* end = nullptr;
  const double v = std::strtod(t.c_str(), &end);
  if (end != t.c_str() + t.size() || !std::isfinite(v)) return false;
  *value = v;
  return true;
}

bool parse_date_time(const std::string& text, double* unix_s) {
  static const std::regex re(R"(\s*(\d{4})[-:](\d{2})[-:](\d{2})[ T](\d{2}):(\d{2}):(\d{2})(\.\d+)?Z?\s*)");
  std::smatch m;
  if (!std::regex_match(text, m, re)) return false;
  std::tm tm{};
  tm.tm_year = std::stoi(m[1]) - 1900;
  tm.tm_mon = std::stoi(m[2]) - 1;
  tm.tm_mday = std::stoi(m[3]);
  tm.tm_hour = std::stoi(m[4]);
  tm.tm_min = std::stoi(m[5]);
  tm.tm_sec = std::stoi(m[6]);
  if (tm.tm_mon < 0 || tm.tm_mon > 11 || tm.tm_mday < 1 || tm.tm_mday > 31 || tm.tm_hour > 23 || tm.tm_min > 59 ||
      tm.tm_sec > 60) {
    return false;
  }
  double fraction = 0.0;
  if (m[7].matched) fraction = std::stod("0" + m[7].str());
  *unix_s = static_cast<double>(timegm(&tm)) + fraction;
  return true;
}

Telemetry parse_srt_text(const std::string& text, const std::string& path, bool skip_bad) {
  Telemetry t;
  t.path = path;
  const std::vector<std::string> lines = split_lines(text);
  size_t i = 0;
  while (i < lines.size()) {
    if (trim(lines[i]).empty()) {
      ++i;
      continue;
    }
    size_t end = i;
    while (end < lines.size() && !trim(lines[end]).empty()) ++end;
    TelemetryRecord r;
    r.line = static_cast<int>(i) + 1;
    try {
      parse_srt_block(lines, i, end, &r);
      t.records.push_back(r);
    } catch (const BadRecord& e) {
      bad(&t, skip_bad, e.line, e.what());
    }
    i = end;
  }
  if (t.records.empty()) throw std::runtime_error(path + ": no usable subtitle blocks");
  return t;
}

Telemetry parse_csv_text(const std::string& text, const std::string& path, bool skip_bad) {
  Telemetry t;
  t.path = path;
  const std::vector<std::string> lines = split_lines(text);
  auto split = [](const std::string& line) {
    std::vector<std::string> cells;
    std::string cell;
    std::istringstream in(line);
    while (std::getline(in, cell, ',')) cells.push_back(trim(cell));
    if (!line.empty() && line.back() == ',') cells.emplace_back();
    return cells;
  };
  size_t header_line = 0;
  while (header_line < lines.size() && (trim(lines[header_line]).empty() || trim(lines[header_line])[0] == '#')) ++header_line;
  if (header_line == lines.size()) throw std::runtime_error(path + ": empty (a header line naming the columns is needed)");
  const std::vector<std::string> header = split(lines[header_line]);
  std::map<std::string, size_t> column;
  for (size_t c = 0; c < header.size(); ++c) column[header[c]] = c;
  const int header_no = static_cast<int>(header_line) + 1;
  for (const char* need : {"time_s", "roll_deg", "pitch_deg", "yaw_deg", "lat_deg", "lon_deg", "alt_m"}) {
    if (!column.count(need)) {
      throw std::runtime_error(path + ":" + std::to_string(header_no) + ": header misses column '" + need +
                               "' (needs time_s,roll_deg,pitch_deg,yaw_deg,range_m|height_m,lat_deg,lon_deg,alt_m)");
    }
  }
  const bool has_range = column.count("range_m") > 0, has_height = column.count("height_m") > 0;
  if (!has_range && !has_height) {
    throw std::runtime_error(path + ":" + std::to_string(header_no) + ": header needs a range_m or a height_m column");
  }
  for (size_t i = header_line + 1; i < lines.size(); ++i) {
    if (trim(lines[i]).empty() || trim(lines[i])[0] == '#') continue;
    const int line_no = static_cast<int>(i) + 1;
    const std::vector<std::string> cells = split(lines[i]);
    if (cells.size() != header.size()) {
      bad(&t, skip_bad, line_no,
          std::to_string(cells.size()) + " columns where the header has " + std::to_string(header.size()));
      continue;
    }
    TelemetryRecord r;
    r.line = line_no;
    std::string error;
    auto get = [&](const std::string& name, double* v) {
      if (error.empty() && !parse_number(cells[column.at(name)], v)) {
        error = "column '" + name + "' is not a number: '" + cells[column.at(name)] + "'";
      }
    };
    get("time_s", &r.time_s);
    get("roll_deg", &r.roll_deg);
    get("pitch_deg", &r.pitch_deg);
    get("yaw_deg", &r.yaw_deg);
    get("lat_deg", &r.lat_deg);
    get("lon_deg", &r.lon_deg);
    get("alt_m", &r.alt_m);
    if (has_range) get("range_m", &r.range_m);
    if (has_height) get("height_m", &r.height_m);
    if (error.empty() && (std::abs(r.lat_deg) > 90.0 || std::abs(r.lon_deg) > 180.0)) error = "lat_deg/lon_deg out of range";
    if (!error.empty()) {
      bad(&t, skip_bad, line_no, error);
      continue;
    }
    r.has_body = true;
    r.has_alt = true;
    r.has_range = has_range;
    r.has_height = has_height;
    t.records.push_back(r);
  }
  if (t.records.empty()) throw std::runtime_error(path + ": no usable data lines");
  return t;
}

Telemetry read_srt(const std::string& path, bool skip_bad) { return parse_srt_text(read_text(path), path, skip_bad); }
Telemetry read_csv(const std::string& path, bool skip_bad) { return parse_csv_text(read_text(path), path, skip_bad); }

}  // namespace nadir::import
