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
  validate_shape(stiffness);
}

void validate_shape(const MountStiffness& stiffness) {
  require(stiffness.exponent >= kMinMountExponent && stiffness.exponent <= kMaxMountExponent, "mount law exponent n",
          stiffness.exponent, "must lie in [1, 5] (the paper's is 2)");
  require(stiffness.preload >= 0.0 && stiffness.preload <= kMaxMountPreload, "mount preload F_p [N]", stiffness.preload,
          "must lie in [0, 20]");
}

double mount_stretch(double force, double stiffness, double exponent, double preload) {
  require_non_negative("force F [N]", force);
  validate(MountStiffness{.forearm = stiffness, .hand = stiffness, .exponent = exponent, .preload = preload});
  if (exponent == 2.0 && preload == 0.0) return std::sqrt(force / std::abs(stiffness));
  if (force <= preload) return 0.0;
  const double stretch_at_reference = std::sqrt(kMountReferenceForce / std::abs(stiffness));
  return stretch_at_reference * std::pow((force - preload) / kMountReferenceForce, 1.0 / exponent);
}

double total_mount_stretch(double force, const MountStiffness& stiffness) {
  return mount_stretch(force, stiffness.forearm, stiffness.exponent, stiffness.preload) +
         mount_stretch(force, stiffness.hand, stiffness.exponent, stiffness.preload);
}

MountTakeUp mount_take_up(const MountStiffness& stiffness) {
  const double c = mount_compliance(stiffness);
  if (stiffness.exponent == 2.0) return {.per_unit = c, .exponent = 2.0, .preload = stiffness.preload};
  // c sqrt(F_r) ((F - F_p) / F_r)^(1/n) = k u with u = (F - F_p)^(1/n).
  return {.per_unit = c * std::sqrt(kMountReferenceForce) * std::pow(kMountReferenceForce, -1.0 / stiffness.exponent),
          .exponent = stiffness.exponent,
          .preload = stiffness.preload};
}

}  // namespace softwrist::physics
