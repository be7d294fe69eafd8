#pragma once
// Every options schema of the tree, in the order of config/default.yaml: the
// configuration reference is rendered from them, and a config is checked by
// running every reader of the shared file over it.

#include <string>
#include <vector>

#include "common/config.h"
#include "common/options_schema.h"

namespace nadir {

// The schemas' sections with their defaults (the reference's content).
std::vector<SectionDoc> all_section_docs();

// docs/reference/configuration.md: a header, then one table per section.
std::string configuration_reference();

// Reads every section of the shared config (config/default.yaml and what is
// laid over it) with its reader, as the processes do at start: throws
// ConfigError naming the file, the key and the nearest known key.
void check_every_section(const Config& root);

}  // namespace nadir
