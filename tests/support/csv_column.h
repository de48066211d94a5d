#pragma once

// Reads one numeric column of a run's CSV file (localization.csv,
// trajectories.csv) by its header name.
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace pavilion::testing {

inline std::vector<double> ReadCsvColumn(const std::filesystem::path& csv,
                                         const std::string& name) {
  std::ifstream in(csv);
  std::string line;
  std::getline(in, line);
  int column = 0;
  {
    std::stringstream header(line);
    std::string field;
    while (std::getline(header, field, ',') && field != name) ++column;
  }
  std::vector<double> values;
  while (std::getline(in, line)) {
    std::stringstream row(line);
    std::string cell;
    for (int c = 0; c <= column; ++c) std::getline(row, cell, ',');
    values.push_back(std::stod(cell));
  }
  return values;
}

}  // namespace pavilion::testing
