#include "scenarios/config/validate.h"

#include "scenarios/config/robot_loader.h"
#include "scenarios/config/scenario.h"
#include "scenarios/config/world_loader.h"
#include "scenarios/config/yaml_reader.h"
#include "scenarios/maps/map_file.h"
#include "sim/world/world.h"

namespace pavilion::scenarios {

std::vector<Diagnostic> ValidateFile(const std::string& path) {
  YamlDocument doc(path);
  if (!doc.ok()) return doc.diagnostics();
  const YAML::Node& root = doc.root();
  std::string kind;
  if (root.IsMap()) {
    for (const auto& kv : root) {
      if (kv.first.Scalar() == "kind" && kv.second.IsScalar()) kind = kv.second.Scalar();
    }
  }
  if (kind == "world") {
    sim::WorldDescription world = ReadWorld(&doc);
    if (!doc.ok()) return doc.diagnostics();
    try {
      sim::World built(std::move(world), sim::WorldOptions{});  // meshes and materials resolve
    } catch (const std::exception& e) {
      return {Diagnostic{path, 0, "", e.what()}};
    }
    return {};
  }
  if (kind == "scenario") {
    try {
      LoadScenarioFile(path);
    } catch (const InputError& e) {
      return e.diagnostics();
    }
    return {};
  }
  if (kind == "robot") {
    ReadRobot(&doc);  // also reads and checks the URDF it names
    return doc.diagnostics();
  }
  if (kind == "map") {
    ReadRobotMap(&doc);
    return doc.diagnostics();
  }
  const int line = root.IsMap() ? root.Mark().line + 1 : 0;
  if (kind.empty()) {
    return {
        Diagnostic{path, line, "kind", "missing top-level 'kind' (world, scenario, robot or map)"}};
  }
  return {Diagnostic{
      path, line, "kind",
      "unknown kind '" + kind + "' (this version validates world, scenario, robot and map files)"}};
}

}  // namespace pavilion::scenarios
