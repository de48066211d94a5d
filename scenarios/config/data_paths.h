#pragma once

#include <string>

namespace pavilion::scenarios {

// Root of the shipped data (worlds/, robots/, scenarios/): $PAVILION_DATA_DIR if
// set, else the source tree the binary was built from.
std::string DataRoot();

// A WORLD argument: a name ("expo_hall", looked up as worlds/<name>/world.yaml
// under DataRoot()) or a path to a world file or folder. Relative paths are taken
// from `base_dir` when it is not empty. Does not check that the file exists.
std::string ResolveWorldPath(const std::string& name_or_path, const std::string& base_dir = "");

// A ROBOT argument: a name ("robox", looked up as robots/<name>/robot.yaml under
// DataRoot()) or a path to a robot file or folder, as ResolveWorldPath.
std::string ResolveRobotPath(const std::string& name_or_path, const std::string& base_dir = "");

}  // namespace pavilion::scenarios
