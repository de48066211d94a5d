#include "scenarios/events/event_log.h"

#include "scenarios/metrics/run_metrics.h"

namespace pavilion::scenarios {

void EventLog::Emit(double time_s, const std::string& type, const EventFields& fields) {
  EventFields record{{"time_s", RoundForJson(time_s)}, {"type", type}};
  if (fields.is_object()) {
    for (const auto& [key, value] : fields.items()) record[key] = value;
  }
  ++counts_[type];
  writer_.Append(record.dump());
  if (listener_) listener_(time_s, type, fields.is_object() ? fields : EventFields::object());
}

}  // namespace pavilion::scenarios
