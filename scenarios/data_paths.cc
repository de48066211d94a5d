#include "scenarios/data_paths.h"

#include <cstdlib>
#include <filesystem>

namespace pavilion::scenarios {

std::string DataRoot() {
  if (const char* env = std::getenv("PAVILION_DATA_DIR"); env != nullptr && *env != '\0') {
    return env;
  }
  return PAVILION_DEFAULT_DATA_DIR;
}

std::string ResolveWorldPath(const std::string& name_or_path, const std::string& base_dir) {
  namespace fs = std::filesystem;
  const bool is_name = name_or_path.find('/') == std::string::npos &&
                       !name_or_path.ends_with(".yaml") && !name_or_path.ends_with(".yml");
  if (is_name) return (fs::path(DataRoot()) / "worlds" / name_or_path / "world.yaml").string();
  fs::path p(name_or_path);
  if (p.is_relative() && !base_dir.empty()) p = fs::path(base_dir) / p;
  if (fs::is_directory(p)) p /= "world.yaml";
  return p.lexically_normal().string();
}

}  // namespace pavilion::scenarios
