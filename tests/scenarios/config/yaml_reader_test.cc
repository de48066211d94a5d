#include "scenarios/config/yaml_reader.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "scenarios/config/input_error.h"
#include "tests/support/test_files.h"

namespace pavilion::scenarios {
namespace {

using pavilion::testing::Contains;

constexpr char kFile[] = "test.yaml";

// Success when `text` contains `part`.
// The 1-based line of `text` holding the first occurrence of `marker`.
int LineOf(const std::string& text, const std::string& marker) {
  const std::size_t at = text.find(marker);
  EXPECT_NE(at, std::string::npos) << "marker '" << marker << "' not in the text";
  int line = 1;
  for (std::size_t i = 0; i < at && i < text.size(); ++i) line += text[i] == '\n' ? 1 : 0;
  return line;
}

// The diagnostic with `key_path`; fails the test (and returns an empty one) when
// there is none.
Diagnostic Find(const std::vector<Diagnostic>& diagnostics, const std::string& key_path) {
  for (const Diagnostic& d : diagnostics) {
    if (d.key_path == key_path) return d;
  }
  ADD_FAILURE() << "no diagnostic for '" << key_path << "'";
  return {};
}

// Confirms that a key no one reads is reported at its own line with its full path.
TEST(YamlReaderTest, ReportsUnknownKeyWithLineAndPath) {
  const std::string text =
      "physics:\n"
      "  rate_hz: 100\n"
      "  rat_hz: 5\n";
  YamlDocument doc(kFile, YAML::Load(text));
  MapReader top(&doc, doc.root(), "");
  MapReader physics(&doc, top.Child("physics", true), "physics");
  EXPECT_DOUBLE_EQ(physics.Number("rate_hz", 200.0, 10.0, 1000.0), 100.0);
  physics.Finish();
  top.Finish();
  ASSERT_EQ(doc.diagnostics().size(), 1u);
  const Diagnostic& d = doc.diagnostics()[0];
  EXPECT_EQ(d.file, kFile);
  EXPECT_EQ(d.line, LineOf(text, "rat_hz"));
  EXPECT_EQ(d.key_path, "physics.rat_hz");
  EXPECT_EQ(d.message, "unknown key");
}

// Confirms that a string where a number belongs is an error naming what was found.
TEST(YamlReaderTest, ReportsWrongType) {
  const std::string text = "mass_kg: abc\n";
  YamlDocument doc(kFile, YAML::Load(text));
  MapReader r(&doc, doc.root(), "");
  EXPECT_DOUBLE_EQ(r.Number("mass_kg", 1.5, 0.0, 10.0), 1.5);  // falls back to the default
  r.Finish();
  ASSERT_EQ(doc.diagnostics().size(), 1u);
  const Diagnostic& d = doc.diagnostics()[0];
  EXPECT_EQ(d.line, 1);
  EXPECT_EQ(d.key_path, "mass_kg");
  EXPECT_TRUE(Contains(d.message, "expected a number"));
  EXPECT_TRUE(Contains(d.message, "'abc'"));
}

// Confirms that the range error states the valid range and the value found.
TEST(YamlReaderTest, ReportsRangeError) {
  const std::string text =
      "outer:\n"
      "  friction: 12\n";
  YamlDocument doc(kFile, YAML::Load(text));
  MapReader r(&doc, doc.root()["outer"], "outer");
  r.Number("friction", 0.5, 0.0, 10.0);
  r.Finish();
  ASSERT_EQ(doc.diagnostics().size(), 1u);
  const Diagnostic& d = doc.diagnostics()[0];
  EXPECT_EQ(d.line, 2);
  EXPECT_EQ(d.key_path, "outer.friction");
  EXPECT_EQ(d.message, "must be in [0, 10], got 12");
}

// Confirms that the YAML spellings of NaN and infinity are rejected as non-finite.
TEST(YamlReaderTest, RejectsNanAndInfinity) {
  for (const std::string value : {".nan", ".NaN", ".inf", "-.inf", ".Inf"}) {
    SCOPED_TRACE(value);
    YamlDocument doc(kFile, YAML::Load("radius: " + value + "\n"));
    MapReader r(&doc, doc.root(), "");
    EXPECT_DOUBLE_EQ(r.Number("radius", 0.25, -1e9, 1e9), 0.25);
    r.Finish();
    ASSERT_EQ(doc.diagnostics().size(), 1u);
    EXPECT_EQ(doc.diagnostics()[0].key_path, "radius");
    EXPECT_TRUE(Contains(doc.diagnostics()[0].message, "finite"));
  }
  // Inside a list of numbers too, with the item's index in the path.
  YamlDocument doc(kFile, YAML::Load("pose: [1, .nan, 0]\n"));
  MapReader r(&doc, doc.root(), "");
  EXPECT_FALSE(r.Numbers("pose", 3, true).has_value());
  r.Finish();
  ASSERT_EQ(doc.diagnostics().size(), 1u);
  EXPECT_EQ(doc.diagnostics()[0].key_path, "pose[1]");
  EXPECT_TRUE(Contains(doc.diagnostics()[0].message, "finite"));
}

// Confirms that a missing required key is reported at the line of its mapping.
TEST(YamlReaderTest, ReportsMissingRequiredKeyAtMappingLine) {
  const std::string text =
      "name: demo\n"
      "shape:\n"
      "  type: cylinder\n"
      "  height: 1.7\n";
  YamlDocument doc(kFile, YAML::Load(text));
  MapReader top(&doc, doc.root(), "");
  MapReader shape(&doc, top.Child("shape", true), "shape");
  EXPECT_EQ(shape.RequiredString("type"), "cylinder");
  EXPECT_FALSE(shape.RequiredNumber("radius", 0.001, 100.0).has_value());
  shape.Number("height", 1.0, 0.001, 100.0);
  shape.Finish();
  top.String("name", "");
  top.Finish();
  ASSERT_EQ(doc.diagnostics().size(), 1u);
  const Diagnostic& d = doc.diagnostics()[0];
  EXPECT_EQ(d.line, LineOf(text, "type: cylinder"));  // where the mapping starts
  EXPECT_EQ(d.key_path, "shape.radius");
  EXPECT_EQ(d.message, "required key is missing");
}

// Confirms that every problem of a document is reported, not just the first.
TEST(YamlReaderTest, ReportsEveryProblemInOneDocument) {
  const std::string text =
      "a: abc\n"
      "b: 50\n"
      "c: .inf\n"
      "d: [1, 2]\n"
      "e: maybe\n"
      "f: purple\n"
      "extra: 1\n";
  YamlDocument doc(kFile, YAML::Load(text));
  MapReader r(&doc, doc.root(), "");
  r.Number("a", 0.0, 0.0, 1.0);
  r.Number("b", 0.0, 0.0, 1.0);
  r.Number("c", 0.0, 0.0, 1.0);
  r.Numbers("d", 3, true);
  r.Bool("e", false);
  r.Choice("f", {"red", "green"}, "red");
  r.RequiredString("g");
  r.Finish();
  EXPECT_FALSE(doc.ok());
  const auto& all = doc.diagnostics();
  ASSERT_EQ(all.size(), 8u);
  EXPECT_EQ(Find(all, "a").line, 1);
  EXPECT_EQ(Find(all, "b").line, 2);
  EXPECT_EQ(Find(all, "c").line, 3);
  EXPECT_EQ(Find(all, "d").line, 4);
  EXPECT_EQ(Find(all, "e").line, 5);
  EXPECT_EQ(Find(all, "f").line, 6);
  EXPECT_TRUE(Contains(Find(all, "f").message, "must be one of red, green"));
  EXPECT_EQ(Find(all, "g").line, 1);
  EXPECT_EQ(Find(all, "extra").line, 7);
  try {
    doc.ThrowIfErrors();
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.diagnostics().size(), 8u);
    EXPECT_EQ(std::string(e.what()), e.diagnostics()[0].ToString());
  }
}

// Confirms the one-line format `file:line: key.path: message` and that unknown parts are left out.
TEST(YamlReaderTest, DiagnosticToStringFormat) {
  EXPECT_EQ((Diagnostic{"worlds/a/world.yaml", 12, "walls[2].thickness", "must be > 0"}).ToString(),
            "worlds/a/world.yaml:12: walls[2].thickness: must be > 0");
  EXPECT_EQ((Diagnostic{"a.yaml", 0, "seed", "bad"}).ToString(), "a.yaml: seed: bad");
  EXPECT_EQ((Diagnostic{"a.yaml", 3, "", "malformed YAML: x"}).ToString(),
            "a.yaml:3: malformed YAML: x");
}

// Confirms that an override replaces a nested key and parses its value as YAML.
TEST(YamlReaderTest, ApplyOverrideReplacesNestedKey) {
  YAML::Node root = YAML::Load("physics:\n  rate_hz: 200\n  gravity_mps2: 9.81\n");
  ApplyOverride(root, "physics.rate_hz=100", false);
  EXPECT_EQ(root["physics"]["rate_hz"].as<double>(), 100.0);
  EXPECT_EQ(root["physics"]["gravity_mps2"].as<double>(), 9.81);
  ApplyOverride(root, "physics.gravity_mps2=[1, 2]", false);
  ASSERT_TRUE(root["physics"]["gravity_mps2"].IsSequence());
  EXPECT_EQ(root["physics"]["gravity_mps2"].size(), 2u);
}

// Confirms that a replaced value carries no line: it is not a line of the file.
TEST(YamlReaderTest, ApplyOverrideValueHasNoFileLine) {
  const std::string text =
      "name: demo\n"
      "physics:\n"
      "  rate_hz: 200\n"
      "  shape: {size: [1, 2]}\n";
  YamlDocument doc(kFile, YAML::Load(text));
  ApplyOverride(doc.mutable_root(), "physics.rate_hz=5", false);
  ApplyOverride(doc.mutable_root(), "physics.shape={size: [1, abc]}", false);
  MapReader top(&doc, doc.root(), "");
  top.String("name", "");
  MapReader physics(&doc, top.Child("physics"), "physics");
  physics.Number("rate_hz", 200.0, 10.0, 1000.0);
  MapReader shape(&doc, physics.Child("shape"), "physics.shape");
  shape.Numbers("size", 2, true);
  shape.Finish();
  physics.Finish();
  top.Finish();
  ASSERT_EQ(doc.diagnostics().size(), 2u);
  EXPECT_EQ(Find(doc.diagnostics(), "physics.rate_hz").line, 0);
  EXPECT_EQ(Find(doc.diagnostics(), "physics.shape.size[1]").line, 0);
  EXPECT_EQ(Find(doc.diagnostics(), "physics.rate_hz").ToString(),
            "test.yaml: physics.rate_hz: must be in [10, 1000], got 5");
}

// Confirms that a numeric path part indexes into a list.
TEST(YamlReaderTest, ApplyOverrideIndexesIntoList) {
  YAML::Node root = YAML::Load("bodies:\n  - id: a\n    mass_kg: 1\n  - id: b\n    mass_kg: 2\n");
  ApplyOverride(root, "bodies.0.mass_kg=3", false);
  EXPECT_EQ(root["bodies"][0]["mass_kg"].as<double>(), 3.0);
  EXPECT_EQ(root["bodies"][1]["mass_kg"].as<double>(), 2.0);
  ApplyOverride(root, "bodies.1=replaced", false);
  EXPECT_EQ(root["bodies"][1].as<std::string>(), "replaced");
}

// Confirms that missing maps are created only when new keys are allowed.
TEST(YamlReaderTest, ApplyOverrideCreatesMissingMapsWhenAllowed) {
  YAML::Node root = YAML::Load("name: demo\n");
  EXPECT_THROW(ApplyOverride(root, "physics.rate_hz=100", false), InputError);
  ApplyOverride(root, "physics.rate_hz=100", true);
  ASSERT_TRUE(root["physics"].IsMap());
  EXPECT_EQ(root["physics"]["rate_hz"].as<double>(), 100.0);
  ApplyOverride(root, "outputs.image.width=300", true);
  EXPECT_EQ(root["outputs"]["image"]["width"].as<int>(), 300);
  EXPECT_EQ(root["name"].as<std::string>(), "demo");
}

// The InputError thrown by ApplyOverride(root, assignment), or a failure.
Diagnostic OverrideError(const std::string& yaml, const std::string& assignment) {
  YAML::Node root = YAML::Load(yaml);
  try {
    ApplyOverride(root, assignment, true);
  } catch (const InputError& e) {
    EXPECT_EQ(e.diagnostics().size(), 1u);
    return e.diagnostics().front();
  }
  ADD_FAILURE() << "no InputError for '" << assignment << "'";
  return {};
}

// Confirms that bad overrides throw InputError naming the override.
TEST(YamlReaderTest, ApplyOverrideRejectsBadPaths) {
  const std::string yaml = "name: demo\nbodies:\n  - id: a\n    mass_kg: 1\n";
  const Diagnostic past_end = OverrideError(yaml, "bodies.5.mass_kg=3");
  EXPECT_EQ(past_end.key_path, "bodies.5.mass_kg=3");
  EXPECT_TRUE(Contains(past_end.message, "past the end"));
  EXPECT_TRUE(Contains(OverrideError(yaml, "bodies.first.mass_kg=3").message, "not an index"));
  EXPECT_TRUE(Contains(OverrideError(yaml, "bodies.-1.mass_kg=3").message, "index"));
  EXPECT_TRUE(Contains(OverrideError(yaml, "name.first=x").message, "below a plain value"));
  const Diagnostic no_eq = OverrideError(yaml, "name");
  EXPECT_EQ(no_eq.file, "--set");
  EXPECT_TRUE(Contains(no_eq.message, "key.path=value"));
  EXPECT_TRUE(Contains(OverrideError(yaml, "=3").message, "key.path=value"));
  EXPECT_TRUE(Contains(OverrideError(yaml, "name=[1, 2").message, "not valid YAML"));
}

}  // namespace
}  // namespace pavilion::scenarios
