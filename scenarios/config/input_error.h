#pragma once

#include <stdexcept>
#include <string>
#include <vector>

namespace pavilion::scenarios {

// One problem found in an input file.
struct Diagnostic {
  std::string file;
  int line = 0;          // 1-based; 0 when unknown
  std::string key_path;  // e.g. "walls[2].thickness"; empty for the whole file
  std::string message;

  // "file:line: key.path: message" (parts that are unknown are left out).
  std::string ToString() const;
};

// Thrown when an input file has problems; carries all of them. what() is the
// first diagnostic's line.
class InputError : public std::runtime_error {
 public:
  explicit InputError(std::vector<Diagnostic> diagnostics);
  explicit InputError(Diagnostic diagnostic);
  const std::vector<Diagnostic>& diagnostics() const { return diagnostics_; }

 private:
  std::vector<Diagnostic> diagnostics_;
};

}  // namespace pavilion::scenarios
