#include "scenarios/config/input_error.h"

#include <utility>

namespace pavilion::scenarios {

std::string Diagnostic::ToString() const {
  // Appends piece by piece: GCC 12 warns falsely (-Wrestrict) on chained `+`.
  std::string out;
  out.append(file);
  if (line > 0) out.append(":").append(std::to_string(line));
  out.append(": ");
  if (!key_path.empty()) out.append(key_path).append(": ");
  out.append(message);
  return out;
}

namespace {
std::string FirstLine(const std::vector<Diagnostic>& d) {
  return d.empty() ? std::string("invalid input") : d.front().ToString();
}
}  // namespace

InputError::InputError(std::vector<Diagnostic> diagnostics)
    : std::runtime_error(FirstLine(diagnostics)), diagnostics_(std::move(diagnostics)) {}

InputError::InputError(Diagnostic diagnostic)
    : InputError(std::vector<Diagnostic>{std::move(diagnostic)}) {}

}  // namespace pavilion::scenarios
