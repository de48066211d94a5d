#include "scenarios/output/chart_js.h"

#include <fstream>
#include <sstream>
#include <stdexcept>

namespace pavilion::scenarios {

const std::string& ChartJsSource() {
  static const std::string source = [] {
    const char* path = PAVILION_CHART_JS_PATH;
    std::ifstream in(path, std::ios::binary);
    if (!in) {
      throw std::runtime_error(std::string(path) +
                               ": cannot read Chart.js (install Debian's libjs-chart.js)");
    }
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
  }();
  return source;
}

std::string ChartJsScriptTag() {
  // "</script" cannot occur in the minified library; checked to be sure the
  // page stays well formed.
  const std::string& js = ChartJsSource();
  if (js.find("</script") != std::string::npos) {
    throw std::runtime_error("Chart.js source holds </script: cannot be inlined");
  }
  return "<script>\n" + js + "\n</script>\n";
}

}  // namespace pavilion::scenarios
