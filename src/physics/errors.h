#pragma once
// The one error type of the physics core: a parameter outside the model's domain. The message names the
// parameter, its value and the allowed range, so a user can find the bad field in their file.

#include <cmath>
#include <stdexcept>
#include <string>
#include <string_view>

namespace softwrist::physics {

class InvalidParameter : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

// Throws InvalidParameter("<name> = <value>: <requirement>").
[[noreturn]] void fail_requirement(std::string_view name, double value, std::string_view requirement);
// Throws InvalidParameter("<name> = <value>: <requirement>") unless `ok`. Inline, so that a check that holds costs
// a branch, not a call: the plugin's force law checks its pressure every step of every muscle (`softwrist bench sim`).
inline void require(bool ok, std::string_view name, double value, std::string_view requirement) {
  if (!ok) fail_requirement(name, value, requirement);
}

inline void require_finite(std::string_view name, double value) {
  require(std::isfinite(value), name, value, "must be a finite number");
}
inline void require_positive(std::string_view name, double value) {
  require(std::isfinite(value) && value > 0.0, name, value, "must be a finite number > 0");
}
inline void require_non_negative(std::string_view name, double value) {
  require(std::isfinite(value) && value >= 0.0, name, value, "must be a finite number >= 0");
}

}  // namespace softwrist::physics
