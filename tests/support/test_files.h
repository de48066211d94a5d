#pragma once

// Helpers for tests that write input files: a fresh folder per test, file
// writing, locating lines in the text written, and options' Validate() messages.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace pavilion::testing {

// A fresh, empty folder for the running test.
inline std::filesystem::path TestDir() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() /
      (std::string("pavilion_test_") + info->test_suite_name() + "_" + info->name());
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

// Writes `text` to dir/name and returns the path.
inline std::string WriteFile(const std::filesystem::path& dir, const std::string& name,
                             const std::string& text) {
  const std::filesystem::path path = dir / name;
  std::ofstream out(path, std::ios::binary);
  out << text;
  return path.string();
}

// The 1-based line of `text` holding the first occurrence of `marker`.
inline int LineOf(const std::string& text, const std::string& marker) {
  const std::size_t at = text.find(marker);
  EXPECT_NE(at, std::string::npos) << "marker '" << marker << "' not in the text";
  return 1 +
         static_cast<int>(std::count(text.begin(), text.begin() + std::min(at, text.size()), '\n'));
}

// What `options.Validate()` throws (std::invalid_argument); empty when it accepts them.
template <typename Options>
std::string ValidateMessage(const Options& options) {
  try {
    options.Validate();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

// `value` written so that YAML reads back the same double.
inline std::string ExactText(double value) {
  char text[64];
  std::snprintf(text, sizeof text, "%.17g", value);
  return text;
}

inline ::testing::AssertionResult Contains(const std::string& text, const std::string& part) {
  if (text.find(part) != std::string::npos) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "'" << text << "' does not contain '" << part << "'";
}

// The folder of the real CARMEN logs: $PAVILION_CARMEN_DIR, else
// ../shared/data/carmen beside the source tree, else /work/shared/data/carmen
// (where the project's machines keep it). Empty when none exists; tests on the
// real logs skip then, saying so.
inline std::string CarmenDataDir() {
  std::vector<std::filesystem::path> candidates;
  if (const char* env = std::getenv("PAVILION_CARMEN_DIR")) candidates.emplace_back(env);
  candidates.push_back(std::filesystem::path(PAVILION_SOURCE_DIR) / ".." / "shared" / "data" /
                       "carmen");
  candidates.emplace_back("/work/shared/data/carmen");
  for (const auto& c : candidates) {
    if (std::filesystem::exists(c / "intel-corrected.log.gz")) return c.lexically_normal().string();
  }
  return "";
}

// A world file of one square room: a 20 m concrete floor and closed concrete
// walls (0.2 m thick, 2.5 m high) `half_width_m` from the centre.
inline std::string WalledRoomWorld(const std::string& name, double half_width_m = 5.0) {
  const std::string h = std::to_string(half_width_m);
  return "kind: world\n"
         "name: " +
         name +
         "\n"
         "materials:\n"
         "  concrete: {friction: 0.8}\n"
         "floor: {min: [-10, -10], max: [10, 10], material: concrete}\n"
         "walls:\n"
         "  - {id: outline, points: [[-" +
         h + ", -" + h + "], [" + h + ", -" + h + "], [" + h + ", " + h + "], [-" + h + ", " + h +
         "]], closed: true,\n"
         "     thickness: 0.2, height: 2.5, material: concrete}\n";
}

}  // namespace pavilion::testing
