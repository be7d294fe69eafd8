#pragma once
// One schema per options section (COLMAP's option manager, Cartographer's
// "no key goes unread"): each key is declared once with its type, unit,
// default (taken from the options struct), allowed range or values and a
// one-line description. The schema reads a section into the struct, refuses
// keys it does not declare (naming the nearest known one), checks a struct's
// values (Check()) and describes itself for the configuration reference
// (nadir_config --config-reference).
//
// Keys may be dotted ("feature_depth.anchor_radius": a subsection's key);
// fields are reached through a chain of member pointers, so a key can land in
// a nested struct: number("layer_min_fraction", ..., &T::solver,
// &SolverOptions::layers, &Layers::min_fraction).

#include <cmath>
#include <cstdint>
#include <functional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "common/config.h"

namespace nadir {

// What the reference says about one key.
struct KeyDoc {
  std::string key;            // dotted, relative to the section
  std::string type;           // number, integer, bool, choice, text
  std::string unit;           // "" when dimensionless
  std::string default_value;  // as it would be written in YAML
  std::string allowed;        // "[lo, hi]", "a | b | c" or ""
  std::string doc;            // one line
};

struct SectionDoc {
  std::string path;  // e.g. "vo_solver"
  std::string doc;   // one line
  std::vector<KeyDoc> keys;
};

// Formats a number as the reference and the errors print it.
std::string format_option_value(double value);
std::string format_option_value(int64_t value);

// Refuses the first key of `section` (recursively into subsections) that is
// neither one of `known` (dotted, relative to the section) nor under one of
// `foreign` (subsections another schema reads): a ConfigError naming the
// source, the full key path, its line and the nearest known key.
void require_declared_keys(const Config& section, const std::vector<std::string>& known,
                           const std::vector<std::string>& foreign = {});

// The known key closest to `key` by edit distance ("" when none is close).
std::string nearest_key(const std::string& key, const std::vector<std::string>& known);

// Markdown for the configuration reference: one table per section.
std::string render_reference(const std::vector<SectionDoc>& sections);

namespace schema_detail {

template <class T, class... M>
auto& reach(T& t, M... path) {  // T may be const
  return (t.*....*path);
}

template <class V>
std::string show(const V& v) {
  if constexpr (std::is_same_v<V, bool>) {
    return v ? "true" : "false";
  } else if constexpr (std::is_floating_point_v<V>) {
    return format_option_value(static_cast<double>(v));
  } else {
    return format_option_value(static_cast<int64_t>(v));
  }
}

// The section holding a dotted key, and the key's last part.
std::pair<Config, std::string> locate(const Config& section, const std::string& dotted);
// The subsection at a dotted path (empty when absent).
Config descend(const Config& section, const std::string& dotted);

}  // namespace schema_detail

template <class T>
class OptionsSchema {
 public:
  struct Entry {
    KeyDoc doc;
    // Reads the key when present (the field keeps its value when absent).
    std::function<void(const Config& section, T& out)> read;
    // "" when the value is allowed, else what is wrong ("= 3 is out of range [5, 10000]").
    std::function<std::string(const T& value)> check;
    std::function<std::string(const T& value)> show;
  };

  OptionsSchema(std::string path, std::string doc) : path_(std::move(path)), doc_(std::move(doc)) {}

  // A number in [lo, hi] (integers and floating point alike).
  template <class... M>
  OptionsSchema& number(const std::string& key, double lo, double hi, const std::string& unit,
                        const std::string& doc, M... path) {
    return scaled(key, 1.0, lo, hi, unit, doc, path...);
  }

  // A number written in the config in one unit and kept in another: the
  // field holds value * scale (rounded to the nearest integer for integer
  // fields); lo, hi and the default are in the config's unit.
  template <class... M>
  OptionsSchema& scaled(const std::string& key, double scale, double lo, double hi, const std::string& unit,
                        const std::string& doc, M... path) {
    return add_number(key, scale, lo, false, hi, unit, doc, path...);
  }

  // A number in (lo, hi]: strictly above lo.
  template <class... M>
  OptionsSchema& above(const std::string& key, double lo, double hi, const std::string& unit, const std::string& doc,
                       M... path) {
    return add_number(key, 1.0, lo, true, hi, unit, doc, path...);
  }

  template <class... M>
  OptionsSchema& add_number(const std::string& key, double scale, double lo, bool lo_open, double hi,
                            const std::string& unit, const std::string& doc, M... path) {
    using V = std::decay_t<decltype(schema_detail::reach(std::declval<T&>(), path...))>;
    static_assert(std::is_arithmetic_v<V> && !std::is_same_v<V, bool>, "number() takes a numeric field");
    Entry e;
    const bool integral = std::is_integral_v<V> && scale == 1.0;
    e.doc = KeyDoc{key, integral ? "integer" : "number", unit, "", range_text<V>(lo, lo_open, hi, scale), doc};
    auto to_config = [scale](const V& v) { return static_cast<double>(v) / scale; };
    e.read = [key, scale, path...](const Config& section, T& out) {
      const auto [c, leaf] = schema_detail::locate(section, key);
      if (!c.has(leaf)) return;
      if constexpr (std::is_integral_v<V>) {
        if (scale == 1.0) {
          schema_detail::reach(out, path...) = c.template get<V>(leaf);
          return;
        }
        const double v = c.template get<double>(leaf) * scale;
        schema_detail::reach(out, path...) = static_cast<V>(v + (v >= 0 ? 0.5 : -0.5));
      } else {
        schema_detail::reach(out, path...) = static_cast<V>(c.template get<double>(leaf) * scale);
      }
    };
    e.check = [lo, lo_open, hi, scale, to_config, path...](const T& value) -> std::string {
      const V v = schema_detail::reach(value, path...);
      const double x = to_config(v);
      if ((lo_open ? x > lo : x >= lo) && x <= hi) return "";
      return "= " + (scale == 1.0 ? schema_detail::show(v) : format_option_value(x)) + " is out of range " +
             range_text<V>(lo, lo_open, hi, scale);
    };
    e.show = [scale, to_config, path...](const T& value) {
      const V v = schema_detail::reach(value, path...);
      return scale == 1.0 ? schema_detail::show(v) : format_option_value(to_config(v));
    };
    entries_.push_back(std::move(e));
    return *this;
  }

  template <class... M>
  OptionsSchema& flag(const std::string& key, const std::string& doc, M... path) {
    Entry e;
    e.doc = KeyDoc{key, "bool", "", "", "true | false", doc};
    e.read = [key, path...](const Config& section, T& out) {
      const auto [c, leaf] = schema_detail::locate(section, key);
      if (c.has(leaf)) schema_detail::reach(out, path...) = c.template get<bool>(leaf);
    };
    e.check = [](const T&) { return std::string(); };
    e.show = [path...](const T& value) { return schema_detail::show(schema_detail::reach(value, path...)); };
    entries_.push_back(std::move(e));
    return *this;
  }

  // A list of N numbers, each in [lo, hi] (an Eigen vector or anything with
  // operator[] and N elements).
  template <int N, class... M>
  OptionsSchema& numbers(const std::string& key, double lo, double hi, const std::string& unit,
                         const std::string& doc, M... path) {
    Entry e;
    const std::string range = "[" + format_option_value(lo) + ", " + format_option_value(hi) + "] each";
    e.doc = KeyDoc{key, "list of " + std::to_string(N) + " numbers", unit, "", range, doc};
    e.read = [key, path...](const Config& section, T& out) {
      const auto [c, leaf] = schema_detail::locate(section, key);
      if (!c.has(leaf)) return;
      const auto values = c.template get<std::vector<double>>(leaf);
      if (values.size() != static_cast<size_t>(N)) {
        throw c.error(leaf, "must have " + std::to_string(N) + " numbers, has " + std::to_string(values.size()));
      }
      auto& field = schema_detail::reach(out, path...);
      for (int i = 0; i < N; ++i) field[i] = values[static_cast<size_t>(i)];
    };
    e.check = [lo, hi, range, path...](const T& value) -> std::string {
      const auto& field = schema_detail::reach(value, path...);
      for (int i = 0; i < N; ++i) {
        if (!(field[i] >= lo && field[i] <= hi)) return "= " + format_option_value(double(field[i])) + " is out of range " + range;
      }
      return "";
    };
    e.show = [path...](const T& value) {
      const auto& field = schema_detail::reach(value, path...);
      std::string text = "[";
      for (int i = 0; i < N; ++i) text += (i ? ", " : "") + format_option_value(double(field[i]));
      return text + "]";
    };
    entries_.push_back(std::move(e));
    return *this;
  }

  // Free text (a device path, an address, a channel name).
  template <class... M>
  OptionsSchema& text(const std::string& key, const std::string& doc, M... path) {
    Entry e;
    e.doc = KeyDoc{key, "text", "", "", "", doc};
    e.read = [key, path...](const Config& section, T& out) {
      const auto [c, leaf] = schema_detail::locate(section, key);
      if (c.has(leaf)) schema_detail::reach(out, path...) = c.template get<std::string>(leaf);
    };
    e.check = [](const T&) { return std::string(); };
    e.show = [path...](const T& value) { return "\"" + schema_detail::reach(value, path...) + "\""; };
    entries_.push_back(std::move(e));
    return *this;
  }

  // One of named values: an enum (names paired with values) or a string
  // field (names only: choice<std::string>(key, {{"a", "a"}, ...})).
  template <class V, class... M>
  OptionsSchema& choice(const std::string& key, std::vector<std::pair<std::string, V>> names,
                        const std::string& doc, M... path) {
    Entry e;
    std::string list;
    for (const auto& n : names) list += (list.empty() ? "" : " | ") + n.first;
    e.doc = KeyDoc{key, "choice", "", "", list, doc};
    e.read = [key, names, list, path...](const Config& section, T& out) {
      const auto [c, leaf] = schema_detail::locate(section, key);
      if (!c.has(leaf)) return;
      const std::string text = c.template get<std::string>(leaf);
      for (const auto& n : names) {
        if (n.first == text) {
          schema_detail::reach(out, path...) = n.second;
          return;
        }
      }
      throw c.error(leaf, "= '" + text + "' is not one of " + list);
    };
    e.check = [names, list, path...](const T& value) -> std::string {
      const V& v = schema_detail::reach(value, path...);
      for (const auto& n : names) {
        if (n.second == v) return "";
      }
      if constexpr (std::is_same_v<V, std::string>) return "= '" + v + "' is not one of " + list;
      return "is not one of " + list;
    };
    e.show = [names, path...](const T& value) -> std::string {
      const V& v = schema_detail::reach(value, path...);
      for (const auto& n : names) {
        if (n.second == v) return n.first;
      }
      return "?";
    };
    entries_.push_back(std::move(e));
    return *this;
  }

  // A condition between fields that no single key's range says
  // ("replenish_below <= features_per_cell"); reported against `key`.
  OptionsSchema& rule(const std::string& key, std::function<bool(const T&)> ok, const std::string& what) {
    return rule(key, std::move(ok), [what](const T&) { return what; });
  }
  // The same with a message built from the values ("= 4 is out of range [1, 3]").
  OptionsSchema& rule(const std::string& key, std::function<bool(const T&)> ok,
                      std::function<std::string(const T&)> what) {
    rules_.push_back(Rule{key, std::move(ok), std::move(what)});
    return *this;
  }

  // A number field at most another field (klt_predicted_levels <= klt_pyramid_levels):
  // reported as "= v is out of range [lo, bound]".
  template <class V>
  OptionsSchema& at_most(const std::string& key, V lo, std::function<V(const T&)> value,
                         std::function<V(const T&)> bound) {
    return rule(
        key, [value, bound](const T& o) { return value(o) <= bound(o); },
        [lo, value, bound](const T& o) {
          return "= " + schema_detail::show(value(o)) + " is out of range [" + schema_detail::show(lo) + ", " +
                 schema_detail::show(bound(o)) + "]";
        });
  }

  // The keys of another section's schema, read into a member (vo_solver's
  // `uncertainty:` subsection). Its keys appear under `prefix.`.
  template <class U, class... M>
  OptionsSchema& include(const std::string& prefix, const OptionsSchema<U>& sub, M... path) {
    for (const auto& s : sub.entries()) {
      Entry e;
      e.doc = s.doc;
      e.doc.key = prefix + "." + s.doc.key;
      const auto sub_read = s.read;
      const auto sub_check = s.check;
      const auto sub_show = s.show;
      e.read = [prefix, sub_read, path...](const Config& section, T& out) {
        sub_read(schema_detail::descend(section, prefix), schema_detail::reach(out, path...));
      };
      e.check = [sub_check, path...](const T& v) { return sub_check(schema_detail::reach(v, path...)); };
      e.show = [sub_show, path...](const T& v) { return sub_show(schema_detail::reach(v, path...)); };
      entries_.push_back(std::move(e));
    }
    for (const auto& r : sub.rules()) {
      rules_.push_back(Rule{prefix + "." + r.key,
                            [ok = r.ok, path...](const T& v) { return ok(schema_detail::reach(v, path...)); },
                            [what = r.what, path...](const T& v) { return what(schema_detail::reach(v, path...)); }});
    }
    return *this;
  }

  // A subsection this schema does not read (another schema does): its keys
  // are not refused here.
  OptionsSchema& foreign(const std::string& subsection) {
    foreign_.push_back(subsection);
    return *this;
  }

  // Refuses unknown keys, reads every declared key present into `out` and
  // checks the result. Errors name section.source() and the full key path.
  void read(const Config& section, T* out) const {
    require_declared_keys(section, keys(), foreign_);
    for (const auto& e : entries_) e.read(section, *out);
    check(*out, section);
  }
  T read(const Config& section) const {
    T out;
    read(section, &out);
    return out;
  }

  // Throws ConfigError naming the first key whose value is not allowed.
  void check(const T& value, const Config& where) const {
    for (const auto& e : entries_) {
      const std::string what = e.check(value);
      if (!what.empty()) throw where.error(e.doc.key, what);
    }
    for (const auto& r : rules_) {
      if (!r.ok(value)) throw where.error(r.key, r.what(value));
    }
  }
  // The same for a struct built in code (the options structs' Check()):
  // errors name the full key path.
  void check(const T& value) const { check(value, Config(YAML::Node(YAML::NodeType::Map), "options", path_)); }

  std::vector<std::string> keys() const {
    std::vector<std::string> k;
    for (const auto& e : entries_) k.push_back(e.doc.key);
    return k;
  }

  // The reference's section, defaults taken from `defaults`.
  SectionDoc describe(const T& defaults = T()) const {
    SectionDoc d{path_, doc_, {}};
    for (const auto& e : entries_) {
      KeyDoc k = e.doc;
      k.default_value = e.show(defaults);
      d.keys.push_back(k);
    }
    return d;
  }

  struct Rule {
    std::string key;
    std::function<bool(const T&)> ok;
    std::function<std::string(const T&)> what;
  };
  const std::vector<Entry>& entries() const { return entries_; }
  const std::vector<Rule>& rules() const { return rules_; }
  const std::string& path() const { return path_; }

 private:
  template <class V>
  static std::string range_text(double lo, bool lo_open, double hi, double scale) {
    const std::string open = lo_open ? "(" : "[";
    if (std::is_integral_v<V> && scale == 1.0) {
      return open + format_option_value(static_cast<int64_t>(lo)) + ", " +
             format_option_value(static_cast<int64_t>(hi)) + "]";
    }
    return open + format_option_value(lo) + ", " + format_option_value(hi) + "]";
  }

  std::string path_;
  std::string doc_;
  std::vector<Entry> entries_;
  std::vector<Rule> rules_;
  std::vector<std::string> foreign_;
};

}  // namespace nadir
