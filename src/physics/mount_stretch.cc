#include "physics/mount_stretch.h"

namespace softwrist::physics {

const char* to_string(StretchMode mode) {
  switch (mode) {
    case StretchMode::kOneShot:
      return "oneshot";
    case StretchMode::kSelfConsistent:
      return "selfconsistent";
    case StretchMode::kNone:
      break;
  }
  return "none";
}

std::optional<StretchMode> parse_stretch_mode(std::string_view name) {
  if (name == "none") return StretchMode::kNone;
  if (name == "oneshot") return StretchMode::kOneShot;
  if (name == "selfconsistent") return StretchMode::kSelfConsistent;
  return std::nullopt;
}

void validate(const MountStiffness& stiffness) {
  require(std::isfinite(stiffness.forearm) && stiffness.forearm != 0.0, "mount stiffness K1 [N/m^2]", stiffness.forearm,
          "must be finite and non-zero (only |K1| is used)");
  require(std::isfinite(stiffness.hand) && stiffness.hand != 0.0, "mount stiffness K2 [N/m^2]", stiffness.hand,
          "must be finite and non-zero (only |K2| is used)");
}

double mount_stretch(double force, double stiffness) {
  require_non_negative("force F [N]", force);
  require(std::isfinite(stiffness) && stiffness != 0.0, "mount stiffness K [N/m^2]", stiffness,
          "must be finite and non-zero (only |K| is used)");
  return std::sqrt(force / std::abs(stiffness));
}

double total_mount_stretch(double force, const MountStiffness& stiffness) {
  return mount_stretch(force, stiffness.forearm) + mount_stretch(force, stiffness.hand);
}

}  // namespace softwrist::physics
