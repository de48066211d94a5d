// A scenario's `reference:` block (issue 21): the figures of a real run keyed
// by the run table's paths, checked when the scenario loads.
#include "scenarios/config/run_reference.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "scenarios/config/input_error.h"
#include "scenarios/config/scenario.h"
#include "tests/support/test_files.h"

namespace pavilion::scenarios {
namespace {

using pavilion::testing::Contains;
using pavilion::testing::LineOf;
using pavilion::testing::TestDir;
using pavilion::testing::WriteFile;

std::string WithReference(const std::string& reference) {
  return "kind: scenario\nname: reference_test\nworld: expo_hall\nduration_s: 1\n" + reference;
}

// Confirms the figures load in file order with their source.
TEST(RunReferenceTest, LoadsFiguresInFileOrder) {
  const std::string text = WithReference(
      "reference:\n"
      "  source: thesis Table 4.3\n"
      "  run_table: {hours: 28, distance_km: 5.013, missions.started: 724}\n");
  const Scenario s = LoadScenarioFile(WriteFile(TestDir(), "s.yaml", text));
  EXPECT_EQ(s.reference.source, "thesis Table 4.3");
  ASSERT_EQ(s.reference.values.size(), 3u);
  EXPECT_EQ(s.reference.values[2].first, "missions.started");
  ASSERT_NE(s.reference.Find("distance_km"), nullptr);
  EXPECT_DOUBLE_EQ(*s.reference.Find("distance_km"), 5.013);
  EXPECT_EQ(s.reference.Find("hours_per_day"), nullptr);
}

// Confirms a key that is no figure of the run table (a misspelling, or a
// section) and a value that is no number are errors naming file, line and key.
TEST(RunReferenceTest, ReportsUnknownFiguresAndBadValues) {
  const std::string text = WithReference(
      "reference:\n"
      "  source: somewhere\n"
      "  run_table:\n"
      "    distance_kms: 5\n"
      "    missions: 3\n"
      "    hours: many\n");
  const std::string path = WriteFile(TestDir(), "s.yaml", text);
  std::vector<Diagnostic> all;
  try {
    LoadScenarioFile(path);
    ADD_FAILURE() << "a bad reference loaded";
  } catch (const InputError& e) {
    all = e.diagnostics();
  }
  ASSERT_EQ(all.size(), 3u);
  EXPECT_EQ(all[0].file, path);
  EXPECT_EQ(all[0].key_path, "reference.run_table.distance_kms");
  EXPECT_EQ(all[0].line, LineOf(text, "distance_kms"));
  EXPECT_TRUE(Contains(all[0].message, "not a figure of the run table"));
  EXPECT_EQ(all[1].key_path, "reference.run_table.missions");
  EXPECT_EQ(all[2].key_path, "reference.run_table.hours");
  EXPECT_EQ(all[2].line, LineOf(text, "hours: many"));
}

}  // namespace
}  // namespace pavilion::scenarios
