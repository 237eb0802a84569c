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
  require(stiffness.shaped_share >= 0.0 && stiffness.shaped_share <= 1.0, "mount law's shaped share s",
          stiffness.shaped_share, "must lie in [0, 1] (1: the shaped law alone, 0: the paper's)");
}

namespace {

// The law in the solver's variable for mounts of total compliance c = sum 1/sqrt|K_i| (mount_stretch.h):
// c sqrt(F_r) ((F - F_p) / F_r)^(1/n) = k u with u = (F - F_p)^(1/n); k = c for the paper's n = 2.
MountTakeUp take_up_of(double compliance, double exponent, double preload) {
  const double per_unit =
      exponent == 2.0 ? compliance
                      : compliance * std::sqrt(kMountReferenceForce) * std::pow(kMountReferenceForce, -1.0 / exponent);
  return {.per_unit = per_unit, .exponent = exponent, .preload = preload};
}

}  // namespace

double mount_stretch(double force, double stiffness, double exponent, double preload) {
  require_non_negative("force F [N]", force);
  validate(MountStiffness{.forearm = stiffness, .hand = stiffness, .exponent = exponent, .preload = preload});
  const MountTakeUp one_mount = take_up_of(1.0 / std::sqrt(std::abs(stiffness)), exponent, preload);
  return one_mount.per_unit * one_mount.unit(force);
}

MountStretches mount_stretches(double force, const MountStiffness& stiffness) {
  const auto one = [&](double k) {
    const double s = stiffness.shaped_share;
    const double shaped = s > 0.0 ? s * mount_stretch(force, k, stiffness.exponent, stiffness.preload) : 0.0;
    return s < 1.0 ? (1.0 - s) * mount_stretch(force, k) + shaped : shaped;
  };
  return {.forearm = one(stiffness.forearm), .hand = one(stiffness.hand)};
}

double total_mount_stretch(double force, const MountStiffness& stiffness) {
  const MountStretches dx = mount_stretches(force, stiffness);
  return dx.forearm + dx.hand;
}

MountTakeUp mount_take_up(const MountStiffness& stiffness) {
  if (stiffness.shaped_share == 0.0) return take_up_of(mount_compliance(stiffness), 2.0, 0.0);
  return take_up_of(mount_compliance(stiffness), stiffness.exponent, stiffness.preload);
}

}  // namespace softwrist::physics
