#include "scenarios/expect/junit.h"

#include <cstdio>
#include <sstream>

#include "scenarios/output/output_files.h"
#include "scenarios/output/report_charts.h"

namespace pavilion::scenarios {
namespace {

// Text for XML 1.0, which allows no control characters but tab, newline and
// return (a crashed run's stderr may hold any byte); attributes are double-quoted.
std::string Xml(const std::string& s) {
  std::string text = s;
  for (char& c : text) {
    if (static_cast<unsigned char>(c) < 0x20 && c != '\t' && c != '\n' && c != '\r') c = '?';
  }
  return EscapeHtml(text);
}

std::string Seconds(double s) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3f", s);
  return buf;
}

void Suite(std::ostringstream& x, const JUnitSuite& s) {
  const bool errored = !s.error.empty();
  const int tests = errored ? 1 : static_cast<int>(s.results.results.size());
  x << "  <testsuite name=\"" << Xml(s.name) << "\" tests=\"" << tests << "\" failures=\""
    << (errored ? 0 : s.results.failures()) << "\" errors=\"" << (errored ? 1 : 0)
    << "\" skipped=\"0\" time=\"" << Seconds(s.time_s) << "\" file=\"" << Xml(s.file) << "\">\n";
  if (errored) {
    x << "    <testcase classname=\"" << Xml(s.name) << "\" name=\"run\" time=\""
      << Seconds(s.time_s) << "\">\n      <error message=\"" << Xml(s.error) << "\">"
      << Xml(s.error_text) << "</error>\n    </testcase>\n";
  }
  for (const ExpectationResult& r :
       errored ? std::vector<ExpectationResult>{} : s.results.results) {
    x << "    <testcase classname=\"" << Xml(s.name) << "\" name=\"" << Xml(r.name)
      << "\" time=\"0\"";
    if (r.status == ExpectationStatus::kPass) {
      x << "/>\n";
      continue;
    }
    const std::string message = r.status == ExpectationStatus::kMissing
                                    ? "missing: " + r.detail
                                    : "measured " + r.measured + ", expected " + r.bound;
    x << ">\n      <failure message=\"" << Xml(message) << "\" type=\"" << ToString(r.status)
      << "\">" << Xml(s.file + ":" + std::to_string(r.line) + ": " + r.name + "\n" + r.detail)
      << "</failure>\n    </testcase>\n";
  }
  x << "  </testsuite>\n";
}

}  // namespace

std::string JUnitXml(const std::vector<JUnitSuite>& suites, const std::string& name) {
  int tests = 0, failures = 0, errors = 0;
  double time_s = 0.0;
  for (const JUnitSuite& s : suites) {
    const bool errored = !s.error.empty();
    tests += errored ? 1 : static_cast<int>(s.results.results.size());
    failures += errored ? 0 : s.results.failures();
    errors += errored ? 1 : 0;
    time_s += s.time_s;
  }
  std::ostringstream x;
  x << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<testsuites name=\"" << Xml(name)
    << "\" tests=\"" << tests << "\" failures=\"" << failures << "\" errors=\"" << errors
    << "\" time=\"" << Seconds(time_s) << "\">\n";
  for (const JUnitSuite& s : suites) Suite(x, s);
  x << "</testsuites>\n";
  return x.str();
}

void WriteJUnit(const std::string& path, const std::vector<JUnitSuite>& suites,
                const std::string& name) {
  WriteFileAtomically(path, JUnitXml(suites, name));
}

}  // namespace pavilion::scenarios
