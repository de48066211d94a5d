#include "scenarios/config/data_paths.h"

#include <cstdlib>
#include <filesystem>

namespace pavilion::scenarios {

std::string DataRoot() {
  if (const char* env = std::getenv("PAVILION_DATA_DIR"); env != nullptr && *env != '\0') {
    return env;
  }
  return PAVILION_DEFAULT_DATA_DIR;
}

namespace {

// A name is looked up as <folder>/<name>/<file> under DataRoot(); a path is
// taken from `base_dir` when relative, with <file> appended to a folder.
std::string ResolveDataPath(const std::string& name_or_path, const std::string& base_dir,
                            const char* folder, const char* file) {
  namespace fs = std::filesystem;
  const bool is_name = name_or_path.find('/') == std::string::npos &&
                       !name_or_path.ends_with(".yaml") && !name_or_path.ends_with(".yml");
  if (is_name) return (fs::path(DataRoot()) / folder / name_or_path / file).string();
  fs::path p(name_or_path);
  if (p.is_relative() && !base_dir.empty()) p = fs::path(base_dir) / p;
  if (fs::is_directory(p)) p /= file;
  return p.lexically_normal().string();
}

}  // namespace

std::string ResolveWorldPath(const std::string& name_or_path, const std::string& base_dir) {
  return ResolveDataPath(name_or_path, base_dir, "worlds", "world.yaml");
}

std::string ResolveRobotPath(const std::string& name_or_path, const std::string& base_dir) {
  return ResolveDataPath(name_or_path, base_dir, "robots", "robot.yaml");
}

}  // namespace pavilion::scenarios
