#pragma once

// The outcome of one expectation of a scenario's `expect:` block (issue 17):
// what `pavilion run` prints, report.html tabulates, expectations.json and the
// JUnit file hold, and sweeps count as a pass rate.

#include <string>
#include <vector>

namespace pavilion::scenarios {

// The exit code of `pavilion run` and `pavilion test` when an expectation
// failed (1 stays bad input, 2 bad usage).
inline constexpr int kExitExpectationFailed = 3;

enum class ExpectationStatus {
  kPass,
  kFail,
  // The metric or section the expectation reads is not in the run's results
  // (e.g. a localization figure of a robot that does not localize): a failure.
  kMissing,
};
const char* ToString(ExpectationStatus status);  // "pass", "fail", "missing"

struct ExpectationResult {
  std::string name;  // the expectation as written, e.g. "robots.*.collisions == 0"
  ExpectationStatus status = ExpectationStatus::kMissing;
  std::string measured;  // for people: "0.031", "robox_1: 2 (of 3)"; empty when missing
  std::string bound;     // "< 0.05", "never", "within 30 s of motion"
  std::string detail;    // why it failed: the first offending robot or event
  int line = 0;          // the expectation's line in the scenario file
};

struct ExpectationResults {
  std::vector<ExpectationResult> results;  // in the file's order
  bool passed() const;                     // every result passes (true when empty)
  int failures() const;                    // kFail and kMissing
};

}  // namespace pavilion::scenarios
