#pragma once
// Laser altimeter line protocols behind one interface. A parser turns one
// line (without its CR/LF) into a range; limits (min/max range, signal) are
// applied by the bridge so every protocol is judged the same way.

#include <memory>
#include <string>
#include <string_view>

namespace nadir {
class Config;
}

namespace nadir::ins_bridge {

struct AltimeterReading {
  bool parsed = false;          // false: the line is not this protocol
  bool no_return = false;       // the device said it saw no target
  double range_m = 0.0;
  float signal_quality = -1.0f; // 0..1, -1 when the protocol does not give one
  std::string error;            // why parsing failed
};

class AltimeterLineParser {
 public:
  virtual ~AltimeterLineParser() = default;
  virtual AltimeterReading parse(std::string_view line) const = 0;
  virtual std::string name() const = 0;
};

// LightWare-style ASCII (SF0x/SF1x serial output): "<metres>[ m][,| ]<strength>%"
// e.g. "123.45", "123.45 m", "123.45 m 87%". "--.--" or a negative distance
// means no return.
class LightwareAsciiParser : public AltimeterLineParser {
 public:
  AltimeterReading parse(std::string_view line) const override;
  std::string name() const override { return "lightware"; }
};

// "<prefix><number><spaces><unit>[<spaces><quality_prefix><0..100>]" with the
// prefix, unit (m, cm, mm, ft) and quality prefix from config; a line equal
// to `no_return_token` means no return.
struct NumberUnitOptions {
  std::string prefix;             // e.g. "D=" or "" (leading spaces always allowed)
  std::string unit = "m";         // m | cm | mm | ft
  std::string quality_prefix;     // e.g. "Q=" (empty: no quality field)
  std::string no_return_token;    // e.g. "NO TARGET" (empty: none)
  void Check(const std::string& source) const;
};

class NumberUnitParser : public AltimeterLineParser {
 public:
  explicit NumberUnitParser(NumberUnitOptions options);
  AltimeterReading parse(std::string_view line) const override;
  std::string name() const override { return "number_unit"; }

 private:
  NumberUnitOptions options_;
  double scale_ = 1.0;  // unit -> metres
};

// Unit name -> metres per unit; false when unknown.
bool unit_scale(const std::string& unit, double* metres_per_unit);

}  // namespace nadir::ins_bridge
