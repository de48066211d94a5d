#pragma once

// events.jsonl: one JSON object per line — the scripted events as they happen
// and the detected ones (collision, bumper, lost, route_done), each with its
// simulation time and type first — and the count of each type for metrics.

#include <cstdint>
#include <map>
#include <string>

#include "scenarios/events/event.h"
#include "scenarios/output/output_files.h"

namespace pavilion::scenarios {

class EventLog {
 public:
  explicit EventLog(const std::string& path) : writer_(path) {}
  // Appends {"time_s": t (6 decimals), "type": type, fields...}.
  void Emit(double time_s, const std::string& type, const EventFields& fields = {});
  void Flush() { writer_.Flush(); }
  const std::map<std::string, std::int64_t>& counts() const { return counts_; }

 private:
  LineWriter writer_;
  std::map<std::string, std::int64_t> counts_;
};

}  // namespace pavilion::scenarios
