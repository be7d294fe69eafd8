#pragma once
// Where things are, resolved from the running executable (build/bin/..) so
// nothing machine-specific is written into the repository.

#include <string>

namespace nadir {

// The checkout root: NADIR_ROOT if set, else the folder two levels above the
// executable that holds config/. Throws std::runtime_error when not found.
std::string checkout_root();
// NADIR_CONFIG if set, else <checkout>/config/default.yaml.
std::string default_config_path();

}  // namespace nadir
