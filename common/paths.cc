#include "common/paths.h"

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <stdexcept>

namespace nadir {
namespace fs = std::filesystem;

std::string checkout_root() {
  if (const char* env = std::getenv("NADIR_ROOT"); env != nullptr && *env != '\0') return env;
  std::error_code ec;
  fs::path dir = fs::read_symlink("/proc/self/exe", ec).parent_path();
  for (int up = 0; up < 4 && !dir.empty(); ++up) {
    if (fs::exists(dir / "config" / "default.yaml") && fs::exists(dir / "lcmtypes")) return dir.string();
    dir = dir.parent_path();
  }
  throw std::runtime_error("cannot find the nadir checkout above the executable; set NADIR_ROOT");
}

std::string default_config_path() {
  if (const char* env = std::getenv("NADIR_CONFIG"); env != nullptr && *env != '\0') return env;
  return (fs::path(checkout_root()) / "config" / "default.yaml").string();
}

}  // namespace nadir
