#include "common/options_schema.h"

#include <algorithm>
#include <iomanip>

namespace nadir {

std::string format_option_value(double value) {
  std::ostringstream text;
  text << std::setprecision(10) << value;
  return text.str();
}

std::string format_option_value(int64_t value) { return std::to_string(value); }

namespace {

size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = up;
    }
  }
  return row[b.size()];
}

bool under(const std::string& key, const std::string& prefix) {
  return key.size() > prefix.size() && key.compare(0, prefix.size(), prefix) == 0 && key[prefix.size()] == '.';
}

void check_map(const Config& section, const std::string& prefix, const std::vector<std::string>& known,
               const std::vector<std::string>& foreign, const Config& top) {
  for (const auto& item : section.node()) {
    const std::string name = item.first.as<std::string>();
    const std::string key = prefix.empty() ? name : prefix + "." + name;
    if (std::find(foreign.begin(), foreign.end(), key) != foreign.end()) continue;
    if (std::find(known.begin(), known.end(), key) != known.end()) continue;
    const bool is_subsection = std::any_of(known.begin(), known.end(), [&](const std::string& k) { return under(k, key); });
    if (is_subsection && item.second.IsMap()) {
      check_map(section.section(name), key, known, foreign, top);
      continue;
    }
    std::string what = "is not a known key";
    const int line = item.first.Mark().line;
    if (line >= 0) what += " (line " + std::to_string(line + 1) + ")";
    const std::string near = nearest_key(key, known);
    if (!near.empty()) what += "; did you mean " + top.key_path(near) + "?";
    throw top.error(key, what);
  }
}

}  // namespace

std::string nearest_key(const std::string& key, const std::vector<std::string>& known) {
  std::string best;
  size_t best_distance = std::string::npos;
  const std::string leaf = key.substr(key.rfind('.') == std::string::npos ? 0 : key.rfind('.') + 1);
  for (const std::string& k : known) {
    // A key moved to the wrong level ("anchor_radius" for
    // "feature_depth.anchor_radius") is as near as its leaf.
    const std::string k_leaf = k.substr(k.rfind('.') == std::string::npos ? 0 : k.rfind('.') + 1);
    const size_t d = std::min(edit_distance(key, k), edit_distance(leaf, k_leaf) + 1);
    if (d < best_distance) {
      best_distance = d;
      best = k;
    }
  }
  // Close enough to be a typo: a third of the key's length, at least 2 edits.
  const size_t limit = std::max<size_t>(2, leaf.size() / 3);
  return best_distance <= limit ? best : "";
}

void require_declared_keys(const Config& section, const std::vector<std::string>& known,
                           const std::vector<std::string>& foreign) {
  check_map(section, "", known, foreign, section);
}

namespace {
std::string cell(const std::string& text) {
  std::string out;
  for (char c : text) out += c == '|' ? std::string("\\|") : std::string(1, c);
  return out.empty() ? "" : out;
}
}  // namespace

std::string render_reference(const std::vector<SectionDoc>& sections) {
  std::ostringstream md;
  for (const SectionDoc& s : sections) {
    md << "## `" << s.path << "`\n\n" << s.doc << "\n\n";
    md << "| key | type | unit | default | allowed | description |\n";
    md << "| --- | --- | --- | --- | --- | --- |\n";
    for (const KeyDoc& k : s.keys) {
      md << "| `" << k.key << "` | " << k.type << " | " << cell(k.unit) << " | `" << k.default_value << "` | "
         << cell(k.allowed) << " | " << cell(k.doc) << " |\n";
    }
    md << "\n";
  }
  return md.str();
}

namespace schema_detail {

std::pair<Config, std::string> locate(const Config& section, const std::string& dotted) {
  const size_t dot = dotted.find('.');
  if (dot == std::string::npos) return {section, dotted};
  return locate(section.section_or_empty(dotted.substr(0, dot)), dotted.substr(dot + 1));
}

Config descend(const Config& section, const std::string& dotted) {
  const auto [parent, leaf] = locate(section, dotted);
  return parent.section_or_empty(leaf);
}

}  // namespace schema_detail

}  // namespace nadir
