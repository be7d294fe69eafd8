#pragma once
// YAML configuration with errors that name the file, the key and the allowed
// range. Options structs read their fields through Config and check them in a
// Check() that throws ConfigError, so bad config fails at start.

#include <yaml-cpp/yaml.h>

#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace nadir {

class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class Config {
 public:
  // Loads a YAML file; throws ConfigError naming the file (and line) on failure.
  static Config load_file(const std::string& path);
  // Parses YAML text; `source` names it in errors.
  static Config parse(const std::string& yaml_text, const std::string& source);

  Config() = default;
  Config(YAML::Node node, std::string source, std::string path);
  Config(const Config&) = default;
  // Rebinds to the other config's tree. (yaml-cpp's Node::operator= would
  // instead write the other tree into this one's, editing every config that
  // shares it.)
  Config& operator=(const Config& other);

  bool has(const std::string& key) const;
  // Child section; throws if missing. `path` in errors is dotted: tracker.klt.window.
  Config section(const std::string& key) const;
  // Child section, or an empty section when absent (all defaults apply).
  Config section_or_empty(const std::string& key) const;

  template <class T>
  T get(const std::string& key) const {
    const YAML::Node child = node_[key];
    if (!child) throw error(key, "is missing");
    return convert<T>(child, key);
  }

  template <class T>
  T get(const std::string& key, const T& fallback) const {
    const YAML::Node child = node_[key];
    if (!child || child.IsNull()) return fallback;
    return convert<T>(child, key);
  }

  // Reads a number and checks lo <= value <= hi.
  template <class T>
  T get_in_range(const std::string& key, const T& fallback, const T& lo, const T& hi) const {
    const T value = get<T>(key, fallback);
    check_range(key, value, lo, hi);
    return value;
  }

  template <class T>
  void check_range(const std::string& key, const T& value, const T& lo, const T& hi) const {
    if (!(value >= lo && value <= hi)) {
      std::ostringstream text;
      text << "= " << value << " is out of range [" << lo << ", " << hi << "]";
      throw error(key, text.str());
    }
  }

  // Throws ConfigError naming the first key of this section that is not in
  // `known` (a misspelt option must not silently fall back to its default),
  // its line and the nearest known key (options_schema.h).
  void require_known_keys(const std::vector<std::string>& known) const;

  // "file: key 'a.b.c' <what>"
  ConfigError error(const std::string& key, const std::string& what) const;

  // Applies "a.b.c=value" (value parsed as YAML) to this config; throws
  // ConfigError naming the override when it is malformed.
  void apply_override(const std::string& assignment);
  // Applies every leaf of `overlay` (a config fragment such as the one
  // nadir_calibrate writes) as an override: a.b.c=<value>. Sections are
  // merged key by key; a leaf (a number, string or list) replaces the value.
  void apply_overlay(const Config& overlay);

  std::string key_path(const std::string& key) const;
  const std::string& source() const { return source_; }
  const YAML::Node& node() const { return node_; }
  std::string dump() const;

 private:
  template <class T>
  T convert(const YAML::Node& child, const std::string& key) const {
    try {
      return child.as<T>();
    } catch (const YAML::Exception&) {
      throw error(key, "has a value of the wrong type (line " + std::to_string(child.Mark().line + 1) + ")");
    }
  }

  YAML::Node node_ = YAML::Node(YAML::NodeType::Map);
  std::string source_ = "<empty>";
  std::string path_;
};

// Checks a condition on an option and throws a ConfigError naming it.
void require_option(bool ok, const std::string& source, const std::string& key, const std::string& what);

}  // namespace nadir
