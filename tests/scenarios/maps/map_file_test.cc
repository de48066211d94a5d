// Robot map files (docs/map_format.md): exact round trip, deterministic text,
// and one rejection test per kind of bad input, each naming file, line and key.
#include "scenarios/maps/map_file.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "scenarios/config/input_error.h"
#include "scenarios/config/validate.h"
#include "tests/support/robot_map_compare.h"
#include "tests/support/test_files.h"

namespace pavilion::scenarios {
namespace {

using pavilion::testing::ExpectSameMap;

using pavilion::testing::Contains;
using pavilion::testing::LineOf;
using pavilion::testing::TestDir;
using pavilion::testing::WriteFile;

Eigen::Matrix2d Cov(double a, double b, double c) {
  Eigen::Matrix2d m;
  m << a, b, b, c;
  return m;
}

// A map with every kind of item and awkward numbers (thirds, pi, tiny variances).
core::RobotMap SampleMap() {
  core::RobotMap m;
  m.name = "sample_room";
  m.description = "Hand-measured \"by tape\", 2 people\\one afternoon\nsecond line";
  m.beam_height_m = 0.5;
  m.lines.push_back({"far_wall", {std::numbers::pi, 4.0 / 3.0, Cov(1e-7, 1.0 / 3e6, 2.5e-5)}});
  core::Line bottom{-std::numbers::pi / 2.0, 2.0,
                    Cov(2e-6, -1e-7, 3e-5)};  // y = -2, seen from y > -2
  m.segments.push_back({"bottom",
                        bottom,
                        {{-1.5, -2.0}, Cov(2.5e-5, 1e-6, 3e-5)},
                        {{-1.0 / 3.0, -2.0}, Cov(2.5e-5, 0, 2.5e-5)}});
  core::Line left{std::numbers::pi, 3.0, Cov(1e-6, 0, 1e-5)};  // x = -3, seen from x > -3
  m.multi_segment_lines.push_back(
      {"left_wall",
       left,
       {{{{-3.0, 2.0}, Cov(1e-5, 0, 1e-5)}, {{-3.0, 0.5}, Cov(1e-5, 0, 1e-5)}},
        {{{-3.0, -0.4}, Cov(1e-5, 0, 1e-5)}, {{-3.0, -1.9}, Cov(1e-5, 0, 1e-5)}}}});
  m.points.push_back({"column", {{0.1, 0.7}, Cov(4e-6, 0, 4e-6)}, 0.25});
  m.points.push_back({"edge", {{1e-9, -0.7}, Cov(4e-6, 0, 4e-6)}, 0.0});
  m.beacons.push_back({"reflector", {{2.0 / 7.0, 1.25}, Cov(1e-6, 0, 1e-6)}});
  m.beacons.push_back({"foil_column", {{-1.5, 0.75}, Cov(1e-6, 0, 1e-6)}, 0.25});
  m.nodes.push_back({"station_1", {1.0, 1.0, std::numbers::pi / 2.0}, true});
  m.nodes.push_back({"via_1", {0.0, 0.0, 0.0}, false});
  m.nodes.push_back({"dock-B", {-1.0, 1.0, -0.1}, true});
  m.edges.push_back({"station_1", "via_1", std::sqrt(2.0)});
  m.edges.push_back({"via_1", "dock-B", std::sqrt(2.0)});
  m.ghost_points.push_back({"g1", {-2.5, -1.2}});
  m.ghost_points.push_back({"g2", {-2.5, -1.45}});
  return m;
}

// Write -> read gives the same map bit for bit (numbers are printed in their
// shortest exact form), and writing it again gives the same bytes.
TEST(MapFileTest, RoundTripIsExactAndDeterministic) {
  const core::RobotMap map = SampleMap();
  const std::string text = RobotMapToYaml(map);
  EXPECT_EQ(text, RobotMapToYaml(map));
  const std::string path = WriteFile(TestDir(), "map.yaml", text);
  const core::RobotMap back = LoadMapFile(path);
  ExpectSameMap(map, back);
  EXPECT_EQ(RobotMapToYaml(back), text);
  EXPECT_TRUE(ValidateFile(path).empty());
}

// WriteMapFile writes exactly RobotMapToYaml's text.
TEST(MapFileTest, WriteMapFileWritesTheText) {
  const core::RobotMap map = SampleMap();
  const std::string path = (TestDir() / "out" / "map.yaml").string();
  WriteMapFile(path, map);
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_EQ(text.str(), RobotMapToYaml(map));
}

// The writer refuses a map that breaks the invariants instead of writing a
// file the reader would reject.
TEST(MapFileTest, WriterRejectsInvalidMaps) {
  core::RobotMap map = SampleMap();
  map.lines[0].line.r_m = 0.0;
  EXPECT_THROW(RobotMapToYaml(map), std::invalid_argument);
  map = SampleMap();
  map.nodes[1].id = "via 1";
  map.edges.clear();
  EXPECT_THROW(RobotMapToYaml(map), std::invalid_argument);
}

// The example of docs/map_format.md is a valid map with one item of each kind.
TEST(MapFileTest, DocumentedExampleIsValid) {
  std::ifstream in(std::string(PAVILION_SOURCE_DIR) + "/docs/map_format.md");
  std::stringstream doc;
  doc << in.rdbuf();
  const std::string text = doc.str();
  const std::size_t begin = text.find("```yaml\n");
  ASSERT_NE(begin, std::string::npos);
  const std::size_t end = text.find("```", begin + 8);
  ASSERT_NE(end, std::string::npos);
  const std::string path =
      WriteFile(TestDir(), "example.yaml", text.substr(begin + 8, end - begin - 8));
  const core::RobotMap map = LoadMapFile(path);
  EXPECT_EQ(map.lines.size(), 1u);
  EXPECT_EQ(map.segments.size(), 1u);
  EXPECT_EQ(map.multi_segment_lines.size(), 1u);
  EXPECT_EQ(map.points.size(), 1u);
  EXPECT_EQ(map.beacons.size(), 1u);
  EXPECT_EQ(map.nodes.size(), 3u);
  EXPECT_EQ(map.edges.size(), 2u);
  EXPECT_EQ(map.ghost_points.size(), 3u);
  EXPECT_TRUE(ValidateFile(path).empty());
}

// A small valid map in which the tests below break one thing at a marker.
const std::string kValid =
    "kind: map\n"
    "name: test_map\n"
    "beam_height: 0.5\n"
    "features:\n"
    "  - type: segment\n"
    "    id: wall\n"
    "    alpha: 1.5707963267948966\n"
    "    r: 2\n"
    "    cov: [1e-6, 0, 2.5e-5]\n"
    "    from: [1, 2]\n"
    "    from_cov: [2.5e-5, 0, 2.5e-5]\n"
    "    to: [-1, 2]\n"
    "    to_cov: [2.5e-5, 0, 2.5e-5]\n"
    "  - type: point\n"
    "    id: column\n"
    "    position: [0, 1]\n"
    "    cov: [2.5e-5, 0, 2.5e-5]\n"
    "    radius: 0.2\n"
    "nodes:\n"
    "  - {id: station_a, type: station, pose: [0, 0, 0]}\n"
    "  - {id: via_b, type: via, pose: [1, 0, 0]}\n"
    "edges:\n"
    "  - {from: station_a, to: via_b, weight: 1}\n"
    "ghost_points:\n"
    "  - {id: g1, position: [0.5, -1]}\n";

std::string Replace(const std::string& text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  std::string out = text;
  return at == std::string::npos ? out : out.replace(at, from.size(), to);
}

// Loads `text` (which must fail) and checks that the first diagnostic names the
// file, the line of `marker`, the key path and contains `message`; ValidateFile
// must report the same.
void ExpectRejected(const std::string& text, const std::string& marker, const std::string& key_path,
                    const std::string& message, bool validate = true) {
  const std::string path = WriteFile(TestDir(), "map.yaml", text);
  const std::string prefix =
      path + ":" + std::to_string(LineOf(text, marker)) + ": " + key_path + ": ";
  try {
    LoadMapFile(path);
    ADD_FAILURE() << "accepted:\n" << text;
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind(prefix, 0), 0u) << what << "\nexpected to start with " << prefix;
    EXPECT_TRUE(Contains(what, message));
    EXPECT_EQ(what.find('\n'), std::string::npos);
  }
  if (!validate) return;
  const auto diagnostics = ValidateFile(path);
  ASSERT_FALSE(diagnostics.empty());
  EXPECT_EQ(diagnostics.front().ToString().rfind(prefix, 0), 0u);
}

// The valid map itself loads.
TEST(MapFileTest, AcceptsTheBaseMap) {
  const std::string path = WriteFile(TestDir(), "map.yaml", kValid);
  const core::RobotMap map = LoadMapFile(path);
  EXPECT_EQ(map.segments.size(), 1u);
  EXPECT_EQ(map.points.size(), 1u);
  EXPECT_EQ(map.nodes.size(), 2u);
  EXPECT_TRUE(map.nodes[0].station);
  EXPECT_EQ(map.edges.size(), 1u);
  EXPECT_EQ(map.ghost_points.size(), 1u);
}

// A feature type the format does not know.
TEST(MapFileTest, RejectsUnknownFeatureType) {
  ExpectRejected(Replace(kValid, "type: point", "type: pillar"), "type: pillar", "features[1].type",
                 "must be one of line, segment, multi_segment_line, point, beacon");
}

// A key the feature type does not have.
TEST(MapFileTest, RejectsUnknownKey) {
  ExpectRejected(Replace(kValid, "    radius: 0.2\n", "    radius: 0.2\n    colour: red\n"),
                 "colour: red", "features[1].colour", "unknown key");
}

// A covariance that is not positive definite (|cov_12| > sqrt(var_1 var_2)).
TEST(MapFileTest, RejectsNonPositiveDefiniteCovariance) {
  ExpectRejected(Replace(kValid, "cov: [1e-6, 0, 2.5e-5]", "cov: [1e-6, 1e-5, 2.5e-5]"),
                 "cov: [1e-6, 1e-5", "features[0].cov", "not positive definite");
}

// A line with r = 0 has no visible side (eq. B.4).
TEST(MapFileTest, RejectsLineWithZeroR) {
  std::string text = Replace(kValid, "    r: 2\n", "    r: 0\n");
  text = Replace(text, "from: [1, 2]", "from: [1, 0]");
  text = Replace(text, "to: [-1, 2]", "to: [-1, 0]");
  ExpectRejected(text, "r: 0", "features[0].r", "must not be 0");
}

// An edge naming a node that does not exist.
TEST(MapFileTest, RejectsEdgeNamingUnknownNode) {
  ExpectRejected(Replace(kValid, "to: via_b, weight", "to: via_c, weight"), "to: via_c",
                 "edges[0].to", "unknown node 'via_c'");
}

// Two features with one id.
TEST(MapFileTest, RejectsDuplicateFeatureIds) {
  ExpectRejected(Replace(kValid, "id: column", "id: wall"), "id: wall\n    position",
                 "features[1].id", "duplicate id: 'wall'");
}

// Two nodes with one id.
TEST(MapFileTest, RejectsDuplicateNodeIds) {
  ExpectRejected(Replace(kValid, "id: via_b, type", "id: station_a, type"),
                 "id: station_a, type: via", "nodes[1].id", "duplicate id: 'station_a'");
}

// A number that is not finite.
TEST(MapFileTest, RejectsNonFiniteNumbers) {
  ExpectRejected(Replace(kValid, "position: [0, 1]", "position: [.inf, 1]"), "position: [.inf",
                 "features[1].position[0]", "must be a finite number");
  ExpectRejected(Replace(kValid, "alpha: 1.5707963267948966", "alpha: .nan"), "alpha: .nan",
                 "features[0].alpha", "must be a finite number");
}

// A segment endpoint that does not lie on the segment's line.
TEST(MapFileTest, RejectsEndpointOffTheLine) {
  ExpectRejected(Replace(kValid, "from: [1, 2]", "from: [1, 2.01]"), "from: [1, 2.01]",
                 "features[0].from", "off the line");
}

// Multi-segment members out of order along the line's direction.
TEST(MapFileTest, RejectsMultiSegmentMembersOutOfOrder) {
  const std::string multi =
      "  - type: multi_segment_line\n"
      "    id: long_wall\n"
      "    alpha: 0\n"
      "    r: 3\n"
      "    cov: [1e-6, 0, 2.5e-5]\n"
      "    segments:\n"
      "      - {from: [3, 1], from_cov: [1e-5, 0, 1e-5], to: [3, 2], to_cov: [1e-5, 0, 1e-5]}\n"
      "      - {from: [3, -2], from_cov: [1e-5, 0, 1e-5], to: [3, -1], to_cov: [1e-5, 0, 1e-5]}\n";
  const std::string text = Replace(kValid, "nodes:\n", multi + "nodes:\n");
  ExpectRejected(text, "{from: [3, -2]", "features[2].segments[1]", "in order");
}

// A file of another kind is not read as a map (validate reads it as that kind).
TEST(MapFileTest, RejectsOtherKinds) {
  ExpectRejected(Replace(kValid, "kind: map", "kind: world"), "kind: world", "kind",
                 "expected 'map'", /*validate=*/false);
}

}  // namespace
}  // namespace pavilion::scenarios
