#pragma once

// events.jsonl: one JSON object per line — the scripted events as they happen
// and the detected ones (collision, bumper, lost, route_done), each with its
// simulation time and type first — and the count of each type for metrics.

#include <cstdint>
#include <functional>
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
  // Called with every record as it is written (e.g. the expectations' monitor).
  using Listener = std::function<void(double, const std::string&, const EventFields&)>;
  void SetListener(Listener listener) { listener_ = std::move(listener); }

 private:
  LineWriter writer_;
  std::map<std::string, std::int64_t> counts_;
  Listener listener_;
};

}  // namespace pavilion::scenarios
