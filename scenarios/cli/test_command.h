#pragma once

#include <CLI/CLI.hpp>

#include "scenarios/batch/test_suite.h"

namespace pavilion::cli {

// `pavilion test DIR_OR_FILES... [--jobs N] [--junit FILE] [--out DIR]`.
CLI::App* AddTestCommand(CLI::App* app, scenarios::TestSuiteOptions* args);
// Exit 0 when every scenario passed, 3 when some failed or did not complete,
// 1 for bad input (a scenario that does not load: nothing runs), 130/143 interrupted.
int RunTestCommand(const scenarios::TestSuiteOptions& args);

}  // namespace pavilion::cli
