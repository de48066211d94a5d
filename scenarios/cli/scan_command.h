#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <string>

namespace pavilion::cli {

// `pavilion scan WORLD ROBOT --pose x,y,theta --out scan.csv [--png scan.png]`:
// places a robot in a world and casts one scan of each of its lasers.
struct ScanArgs {
  std::string world;  // worlds/<name> name or path
  std::string robot;  // robots/<name> name or path
  std::string pose;   // "x,y,theta" (m, m, rad)
  std::string out;    // CSV file
  std::string png;    // optional top-down picture
  std::int64_t seed = 1;
  bool noise = true;
};

CLI::App* AddScanCommand(CLI::App* app, ScanArgs* args);
// Throws scenarios::InputError for bad files; returns the exit code.
int RunScanCommand(const ScanArgs& args);

}  // namespace pavilion::cli
