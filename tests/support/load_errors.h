#pragma once

// Scenario files that must not load: the one problem their loader reports.

#include <gtest/gtest.h>

#include <string>

#include "scenarios/config/input_error.h"
#include "scenarios/config/scenario.h"
#include "tests/support/test_files.h"

namespace pavilion::testing {

// Expects LoadScenarioFile(path) to fail with exactly one problem, on one
// line, at `key_path` in `path`, whose message contains `says`; returns it.
inline scenarios::Diagnostic ExpectOneLoadError(const std::string& path,
                                                const std::string& key_path,
                                                const std::string& says) {
  try {
    scenarios::LoadScenarioFile(path);
    ADD_FAILURE() << "loaded " << path;
  } catch (const scenarios::InputError& e) {
    EXPECT_EQ(e.diagnostics().size(), 1u) << e.what();
    if (e.diagnostics().empty()) return {};
    const scenarios::Diagnostic& d = e.diagnostics()[0];
    EXPECT_EQ(d.file, path);
    EXPECT_EQ(d.key_path, key_path);
    EXPECT_TRUE(Contains(d.message, says)) << d.ToString();
    EXPECT_EQ(d.ToString().find('\n'), std::string::npos);
    return d;
  }
  return {};
}

}  // namespace pavilion::testing
