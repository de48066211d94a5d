#include "scenarios/config/options_reader.h"

#include <gtest/gtest.h>

#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "scenarios/config/input_error.h"
#include "tests/support/test_files.h"

namespace pavilion::scenarios {
namespace {

using pavilion::testing::LineOf;

constexpr char kFile[] = "test.yaml";

// A component's options as the conventions want them: ranges in Validate() only.
struct ToyOptions {
  double speed_mps = 1.0;  // [0, 2]
  double angle_rad = 0.0;  // [0, pi/2]; key angle_deg
  int count = 3;           // [1, 10]
  bool enabled = false;
  std::optional<double> limit_m;       // when set, > 0
  Eigen::Vector2d offset_m{0.0, 0.0};  // finite
  double min_m = 0.1;                  // [0, max_m]
  double max_m = 1.0;                  // > 0

  void Validate() const {
    if (!(speed_mps >= 0.0 && speed_mps <= 2.0)) {
      throw std::invalid_argument("ToyOptions.speed_mps must be in [0, 2] m/s");
    }
    if (!(angle_rad >= 0.0 && angle_rad <= std::numbers::pi / 2)) {
      throw std::invalid_argument("ToyOptions.angle_rad must be in [0, pi/2] rad");
    }
    if (count < 1 || count > 10) throw std::invalid_argument("ToyOptions.count must be in [1, 10]");
    if (limit_m && !(*limit_m > 0.0)) throw std::invalid_argument("ToyOptions.limit_m must be > 0");
    if (!(max_m > 0.0)) throw std::invalid_argument("ToyOptions.max_m must be > 0");
    if (!(min_m >= 0.0 && min_m <= max_m)) {
      throw std::invalid_argument("ToyOptions.min_m must be in [0, max_m]");
    }
    if (enabled && count == 7) throw std::invalid_argument("seven is unlucky");
  }
};

constexpr double kRadPerDeg = std::numbers::pi / 180.0;

// Reads `text`'s mapping under `toy` into `*options`; returns the diagnostics.
std::vector<Diagnostic> Read(const std::string& text, ToyOptions* options, bool* ok = nullptr) {
  YamlDocument doc(kFile, YAML::Load(text));
  MapReader top(&doc, doc.root(), "");
  MapReader r(&doc, top.Child("toy"), "toy");
  const bool valid = ReadOptions(r, options,
                                 {{"speed_mps", &ToyOptions::speed_mps},
                                  {"angle_deg", "angle_rad", &ToyOptions::angle_rad, kRadPerDeg},
                                  {"count", &ToyOptions::count},
                                  {"enabled", &ToyOptions::enabled},
                                  {"limit_m", &ToyOptions::limit_m},
                                  {"offset_m", &ToyOptions::offset_m},
                                  {"min_m", &ToyOptions::min_m},
                                  {"max_m", &ToyOptions::max_m}});
  r.Finish();
  top.Finish();
  if (ok != nullptr) *ok = valid;
  return doc.diagnostics();
}

// Confirms that present keys are read (numbers scaled), absent ones keep the defaults.
TEST(OptionsReaderTest, ReadsBoundKeysAndKeepsDefaults) {
  ToyOptions o;
  bool ok = false;
  EXPECT_TRUE(
      Read("toy:\n  speed_mps: 1.5\n  angle_deg: 45\n  limit_m: 2\n  offset_m: [1, -1]\n", &o, &ok)
          .empty());
  EXPECT_TRUE(ok);
  EXPECT_EQ(o.speed_mps, 1.5);
  EXPECT_EQ(o.angle_rad, 45 * kRadPerDeg);
  EXPECT_EQ(o.count, 3);
  EXPECT_FALSE(o.enabled);
  EXPECT_EQ(o.limit_m, 2.0);
  EXPECT_EQ(o.offset_m, Eigen::Vector2d(1, -1));
}

// Confirms that Validate()'s error is reported at the key of the field it
// names (the file's key, not the field's name) with its line and message.
TEST(OptionsReaderTest, ReportsValidateErrorAtTheFieldsKey) {
  const std::string text = "toy:\n  speed_mps: 1\n  angle_deg: 100\n";
  ToyOptions o;
  bool ok = true;
  const std::vector<Diagnostic> all = Read(text, &o, &ok);
  EXPECT_FALSE(ok);
  ASSERT_EQ(all.size(), 1u);
  EXPECT_EQ(all[0].ToString(),
            std::string(kFile) + ":" + std::to_string(LineOf(text, "angle_deg")) +
                ": toy.angle_deg: ToyOptions.angle_rad must be in [0, pi/2] rad");
}

// Confirms that every rejected field is reported once, a relation between
// fields at the field named (the mapping's line when its key is absent), and a
// message naming no field at the mapping itself.
TEST(OptionsReaderTest, ReportsEveryRejectedField) {
  const std::string text = "toy:\n  speed_mps: 3\n  count: 11\n  max_m: 0.05\n";
  ToyOptions o;
  std::vector<Diagnostic> all = Read(text, &o);
  ASSERT_EQ(all.size(), 3u);
  EXPECT_EQ(all[0].key_path, "toy.speed_mps");
  EXPECT_EQ(all[0].line, LineOf(text, "speed_mps"));
  EXPECT_EQ(all[1].key_path, "toy.count");
  EXPECT_EQ(all[1].line, LineOf(text, "count"));
  EXPECT_EQ(all[2].key_path, "toy.min_m");  // absent: min 0.1 > max 0.05
  EXPECT_EQ(all[2].line, LineOf(text, "speed_mps"));
  EXPECT_EQ(all[2].message, "ToyOptions.min_m must be in [0, max_m]");

  o = {};
  all = Read("toy:\n  enabled: true\n  count: 7\n", &o);
  ASSERT_EQ(all.size(), 1u);
  EXPECT_EQ(all[0].key_path, "toy");
  EXPECT_EQ(all[0].message, "seven is unlucky");
}

// Confirms that type errors are the reader's: not a number, not finite, not an
// integer, not a bool, a list of the wrong length; Validate() then sees the defaults.
TEST(OptionsReaderTest, ReportsTypeErrors) {
  const std::string text =
      "toy:\n  speed_mps: fast\n  angle_deg: .nan\n  count: 2.5\n  enabled: maybe\n"
      "  offset_m: [1]\n  limit_m: 99999999999999999999\n";
  ToyOptions o;
  const std::vector<Diagnostic> all = Read(text, &o);
  std::vector<std::string> keys;
  for (const Diagnostic& d : all) keys.push_back(d.key_path);
  EXPECT_EQ(keys, (std::vector<std::string>{"toy.speed_mps", "toy.angle_deg", "toy.count",
                                            "toy.enabled", "toy.offset_m"}));
  EXPECT_EQ(o.speed_mps, 1.0);
  EXPECT_EQ(o.count, 3);
  EXPECT_EQ(o.limit_m, 1e20);  // a finite double
}

// Confirms that the field named in a message is its first identifier that is
// a bound field (split at '.'), not a field it is compared with.
TEST(OptionsReaderTest, FindsTheFieldNamedFirst) {
  using options_reader_internal::FieldNamedIn;
  const std::vector<std::string> fields = {"obstruction_distance_m", "stop_distance_m"};
  EXPECT_EQ(
      FieldNamedIn("WanderOptions.stop_distance_m must be in [0, obstruction_distance_m]", fields),
      1u);
  EXPECT_EQ(FieldNamedIn("obstruction_distance_m must be > 0", fields), 0u);
  EXPECT_EQ(FieldNamedIn("xstop_distance_m must be", fields), 2u);
  EXPECT_EQ(FieldNamedIn("", fields), 2u);
}

}  // namespace
}  // namespace pavilion::scenarios
