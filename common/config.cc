#include "common/config.h"

#include <algorithm>

#include "common/options_schema.h"

namespace nadir {

Config Config::load_file(const std::string& path) {
  try {
    return Config(YAML::LoadFile(path), path, "");
  } catch (const YAML::BadFile&) {
    throw ConfigError(path + ": cannot open config file");
  } catch (const YAML::ParserException& e) {
    throw ConfigError(path + ": YAML syntax error at line " + std::to_string(e.mark.line + 1) + ": " + e.msg);
  }
}

Config Config::parse(const std::string& yaml_text, const std::string& source) {
  try {
    return Config(YAML::Load(yaml_text), source, "");
  } catch (const YAML::ParserException& e) {
    throw ConfigError(source + ": YAML syntax error at line " + std::to_string(e.mark.line + 1) + ": " + e.msg);
  }
}

Config::Config(YAML::Node node, std::string source, std::string path)
    : node_(std::move(node)), source_(std::move(source)), path_(std::move(path)) {
  if (node_.IsNull()) node_ = YAML::Node(YAML::NodeType::Map);
  if (!node_.IsMap()) throw ConfigError(source_ + ": " + (path_.empty() ? "top level" : "key '" + path_ + "'") + " must be a map");
}

Config& Config::operator=(const Config& other) {
  if (this == &other) return *this;
  node_.reset(other.node_);
  source_ = other.source_;
  path_ = other.path_;
  return *this;
}

bool Config::has(const std::string& key) const { return static_cast<bool>(node_[key]); }

Config Config::section(const std::string& key) const {
  const YAML::Node child = node_[key];
  if (!child) throw error(key, "is missing (a section is required)");
  if (!child.IsMap()) throw error(key, "must be a map");
  return Config(child, source_, key_path(key));
}

Config Config::section_or_empty(const std::string& key) const {
  if (!has(key)) return Config(YAML::Node(YAML::NodeType::Map), source_, key_path(key));
  return section(key);
}

std::string Config::key_path(const std::string& key) const { return path_.empty() ? key : path_ + "." + key; }

ConfigError Config::error(const std::string& key, const std::string& what) const {
  return ConfigError(source_ + ": key '" + key_path(key) + "' " + what);
}

void Config::require_known_keys(const std::vector<std::string>& known) const {
  // Only this level: a listed key may hold a subsection read elsewhere.
  std::vector<std::string> foreign;
  for (const std::string& k : known) {
    if (node_[k] && node_[k].IsMap()) foreign.push_back(k);
  }
  require_declared_keys(*this, known, foreign);
}

void Config::apply_override(const std::string& assignment) {
  const size_t eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0) {
    throw ConfigError("override '" + assignment + "' must look like section.key=value");
  }
  const std::string path = assignment.substr(0, eq);
  YAML::Node value;
  try {
    value = YAML::Load(assignment.substr(eq + 1));
  } catch (const YAML::ParserException& e) {
    throw ConfigError("override '" + assignment + "': value is not valid YAML: " + e.msg);
  }
  // Walk (and create) the maps along the dotted path. yaml-cpp nodes are
  // handles, so assignment through them edits this config's tree.
  std::vector<YAML::Node> chain{node_};
  size_t start = 0;
  std::vector<std::string> keys;
  while (true) {
    const size_t dot = path.find('.', start);
    keys.push_back(path.substr(start, dot == std::string::npos ? std::string::npos : dot - start));
    if (dot == std::string::npos) break;
    start = dot + 1;
  }
  for (size_t i = 0; i + 1 < keys.size(); ++i) {
    YAML::Node next = chain.back()[keys[i]];
    if (!next || next.IsNull()) {
      chain.back()[keys[i]] = YAML::Node(YAML::NodeType::Map);
      next = chain.back()[keys[i]];
    }
    if (!next.IsMap()) throw ConfigError("override '" + assignment + "': '" + keys[i] + "' is not a section");
    chain.push_back(next);
  }
  chain.back()[keys.back()] = value;
  source_ += " (with " + assignment + ")";
}

std::string Config::dump() const {
  YAML::Emitter out;
  out << node_;
  return out.c_str();
}

namespace {

void collect_leaves(const YAML::Node& node, const std::string& prefix, std::vector<std::string>* assignments) {
  for (const auto& item : node) {
    const std::string path = prefix + item.first.as<std::string>();
    if (item.second.IsMap()) {
      collect_leaves(item.second, path + ".", assignments);
    } else {
      YAML::Emitter value;
      value << YAML::Flow << item.second;
      assignments->push_back(path + "=" + value.c_str());
    }
  }
}

}  // namespace

void Config::apply_overlay(const Config& overlay) {
  std::vector<std::string> assignments;
  collect_leaves(overlay.node(), "", &assignments);
  for (const std::string& a : assignments) apply_override(a);
}

void require_option(bool ok, const std::string& source, const std::string& key, const std::string& what) {
  if (!ok) throw ConfigError(source + ": key '" + key + "' " + what);
}

}  // namespace nadir
