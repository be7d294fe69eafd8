#include "processes/ins_bridge/altimeter_parser.h"

#include <charconv>
#include <cmath>

#include "common/config.h"

namespace nadir::ins_bridge {
namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

// Longest leading number of `s`; advances `s` past it.
bool take_number(std::string_view* s, double* value) {
  std::string_view text = *s;
  if (!text.empty() && text.front() == '+') text.remove_prefix(1);
  const auto r = std::from_chars(text.data(), text.data() + text.size(), *value);
  if (r.ec != std::errc() || !std::isfinite(*value)) return false;
  s->remove_prefix(static_cast<size_t>(r.ptr - s->data()));
  return true;
}

bool printable(std::string_view s) {
  for (char c : s) {
    const auto u = static_cast<unsigned char>(c);
    if (u < 0x20 || u >= 0x7F) {
      if (c != '\t') return false;
    }
  }
  return true;
}

AltimeterReading fail(const std::string& why) {
  AltimeterReading r;
  r.error = why;
  return r;
}

// "<0..100>%"-style quality, with or without the percent sign.
bool take_quality(std::string_view text, float* quality) {
  if (!text.empty() && text.back() == '%') text.remove_suffix(1);
  double value = 0;
  if (!take_number(&text, &value) || !text.empty() || value < 0 || value > 100) return false;
  *quality = static_cast<float>(value / 100.0);
  return true;
}

}  // namespace

bool unit_scale(const std::string& unit, double* metres_per_unit) {
  if (unit == "m") *metres_per_unit = 1.0;
  else if (unit == "cm") *metres_per_unit = 0.01;
  else if (unit == "mm") *metres_per_unit = 0.001;
  else if (unit == "ft") *metres_per_unit = 0.3048;
  else return false;
  return true;
}

AltimeterReading LightwareAsciiParser::parse(std::string_view line) const {
  if (!printable(line)) return fail("line has non-printable bytes");
  std::string_view s = trim(line);
  if (s.empty()) return fail("empty line");
  AltimeterReading r;
  if (s.substr(0, 5) == "--.--") {
    r.parsed = true;
    r.no_return = true;
    return r;
  }
  double distance = 0;
  if (!take_number(&s, &distance)) return fail("no distance at the start of the line");
  s = trim(s);
  if (!s.empty() && s.front() == 'm') s = trim(s.substr(1));
  if (!s.empty() && s.front() == ',') s = trim(s.substr(1));
  if (!s.empty() && !take_quality(s, &r.signal_quality)) return fail("trailing text is not a 0..100 strength");
  r.parsed = true;
  r.no_return = distance < 0;
  r.range_m = distance;
  return r;
}

void NumberUnitOptions::Check(const std::string& source) const {
  double scale = 0;
  require_option(unit_scale(unit, &scale), source, "ins_bridge.altimeter.number_unit.unit",
                 "= '" + unit + "' must be one of m, cm, mm, ft");
}

NumberUnitParser::NumberUnitParser(NumberUnitOptions options) : options_(std::move(options)) {
  options_.Check("number_unit parser");
  unit_scale(options_.unit, &scale_);
}

AltimeterReading NumberUnitParser::parse(std::string_view line) const {
  if (!printable(line)) return fail("line has non-printable bytes");
  std::string_view s = trim(line);
  if (!options_.no_return_token.empty() && s == options_.no_return_token) {
    AltimeterReading r;
    r.parsed = true;
    r.no_return = true;
    return r;
  }
  if (s.substr(0, options_.prefix.size()) != options_.prefix) return fail("line does not start with '" + options_.prefix + "'");
  s = trim(s.substr(options_.prefix.size()));
  double value = 0;
  if (!take_number(&s, &value)) return fail("no number after the prefix");
  s = trim(s);
  if (s.substr(0, options_.unit.size()) != options_.unit) return fail("unit is not '" + options_.unit + "'");
  s = s.substr(options_.unit.size());
  if (!s.empty() && s.front() != ' ' && s.front() != '\t' && s.front() != ',') return fail("unit is not '" + options_.unit + "'");
  s = trim(s);
  if (!s.empty() && s.front() == ',') s = trim(s.substr(1));
  AltimeterReading r;
  if (!s.empty()) {
    if (options_.quality_prefix.empty() || s.substr(0, options_.quality_prefix.size()) != options_.quality_prefix)
      return fail("unexpected text after the unit");
    if (!take_quality(trim(s.substr(options_.quality_prefix.size())), &r.signal_quality))
      return fail("quality is not a number in 0..100");
  }
  r.parsed = true;
  r.no_return = value < 0;
  r.range_m = value * scale_;
  return r;
}

}  // namespace nadir::ins_bridge
