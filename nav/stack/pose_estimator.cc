#include "nav/stack/pose_estimator.h"

namespace pavilion::nav {

const char* LocalizationModeName(LocalizationMode mode) {
  switch (mode) {
    case LocalizationMode::kLocalized:
      return "localized";
    case LocalizationMode::kNotLocalized:
      return "not_localized";
    case LocalizationMode::kLost:
      return "lost";
  }
  return "unknown";
}

}  // namespace pavilion::nav
