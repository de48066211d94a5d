#include "scenarios/expect/expectation.h"

namespace pavilion::scenarios {

const char* ToString(Comparison c) {
  switch (c) {
    case Comparison::kLess:
      return "<";
    case Comparison::kLessEqual:
      return "<=";
    case Comparison::kGreater:
      return ">";
    case Comparison::kGreaterEqual:
      return ">=";
    case Comparison::kEqual:
      return "==";
    case Comparison::kNotEqual:
      return "!=";
  }
  return "?";
}

bool Compare(double measured, Comparison c, double bound) {
  switch (c) {
    case Comparison::kLess:
      return measured < bound;
    case Comparison::kLessEqual:
      return measured <= bound;
    case Comparison::kGreater:
      return measured > bound;
    case Comparison::kGreaterEqual:
      return measured >= bound;
    case Comparison::kEqual:
      return measured == bound;
    case Comparison::kNotEqual:
      return measured != bound;
  }
  return false;
}

bool EventFilter::Matches(const std::string& event_type,
                          const nlohmann::ordered_json& record) const {
  if (event_type != type) return false;
  for (const auto& [key, value] : fields.items()) {
    const auto it = record.find(key);
    if (it == record.end() || *it != value) return false;
  }
  return true;
}

std::string EventFilter::ToString() const {
  std::string s = type;
  for (const auto& [key, value] : fields.items()) {
    s += " " + key + "=" + (value.is_string() ? value.get<std::string>() : value.dump());
  }
  return s;
}

}  // namespace pavilion::scenarios
