#pragma once

// JUnit XML as CI systems read it (Jenkins, GitLab, GitHub reporters): one
// <testsuite> per scenario run with tests, failures, errors and time; one
// <testcase> per expectation, a failure message holding the measured value
// and the bound. A run that did not complete (bad input, a crash, a kill) is
// one <testcase> with an <error> holding what it printed last.

#include <string>
#include <vector>

#include "scenarios/expect/expectation_result.h"

namespace pavilion::scenarios {

struct JUnitSuite {
  std::string name;  // the scenario (file stem, or the run's id)
  std::string file;  // the scenario file
  double time_s = 0.0;
  ExpectationResults results;
  // Non-empty: the run did not complete; `error` says how, `error_text` is
  // its stderr tail.
  std::string error;
  std::string error_text;
};

std::string JUnitXml(const std::vector<JUnitSuite>& suites, const std::string& name = "pavilion");

// Writes the XML atomically; throws std::runtime_error naming the file.
void WriteJUnit(const std::string& path, const std::vector<JUnitSuite>& suites,
                const std::string& name = "pavilion");

}  // namespace pavilion::scenarios
