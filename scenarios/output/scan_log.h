#pragma once

#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

#include "core/types/sensor_data.h"

namespace pavilion::scenarios {

// One scan of a scan log with its ground truth.
struct ScanLogRecord {
  std::string robot;
  core::LaserScan scan;
  core::LaserScanTruth truth;
};

// The scan log `scans.bin` (format in docs/scan_log.md): little-endian binary,
// the magic "PAVSCAN1", the world's element ids (so truth element indices can
// be named), then one record per scan in the order the scans finished.
class ScanLogWriter {
 public:
  // Opens `path` for writing; throws std::runtime_error naming it on failure.
  ScanLogWriter(const std::string& path, const std::vector<std::string>& element_ids);
  void Append(const std::string& robot, const core::LaserScan& scan,
              const core::LaserScanTruth& truth);
  // Flushes; throws std::runtime_error on a write error.
  void Close();
  std::int64_t scans() const { return scans_; }

 private:
  std::string path_;
  std::ofstream out_;
  std::string buffer_;
  std::int64_t scans_ = 0;
};

struct ScanLog {
  std::vector<std::string> element_ids;
  std::vector<ScanLogRecord> records;
};

// Reads a whole scan log; throws std::runtime_error naming the file and the
// byte offset of a truncated or malformed record.
ScanLog ReadScanLog(const std::string& path);

}  // namespace pavilion::scenarios
