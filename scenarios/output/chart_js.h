#pragma once

// Chart.js 3.9 from Debian's libjs-chart.js, for inlining into the self-contained
// HTML pages Pavilion writes (report.html, sweep.html): they open offline.

#include <string>

namespace pavilion::scenarios {

// The library's minified source (read once, cached). Throws std::runtime_error
// naming the file when it is missing (install libjs-chart.js).
const std::string& ChartJsSource();

// A <script> element holding ChartJsSource().
std::string ChartJsScriptTag();

}  // namespace pavilion::scenarios
