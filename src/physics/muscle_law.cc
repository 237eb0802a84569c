#include "physics/muscle_law.h"

#include "physics/errors.h"
#include "physics/plausible_ranges.h"

namespace softwrist::physics {

void validate(const MuscleLaw& law) {
  require_positive("rest_length L0 [m]", law.rest_length);
  require(law.rest_length <= plausible::kMaxLength, "rest_length L0 [m]", law.rest_length, "must be at most 10");
  if (law.stretch_mode != StretchMode::kNone) validate(law.mount_stiffness);
}

StretchedForce stretched_force(const MuscleLaw& law, const FpamForceLaw& force_law, double path_length) {
  const double rest_length = law.rest_length;
  // Eqn. force's contraction ratio inline: L0 > 0 was validated, and the plugin's force must not throw into MuJoCo.
  const auto force_at_length = [&](double length) { return force_law((rest_length - length) / rest_length); };
  return solve_mount_stretch(force_at_length, path_length, law.mount_stiffness, law.stretch_mode);
}

StretchedForce stretched_force(const MuscleLaw& law, double path_length, double pressure) {
  validate(law);
  return stretched_force(law, FpamForceLaw(pressure, law.fpam.at_pressure(pressure), law.fpam.fabric()), path_length);
}

}  // namespace softwrist::physics
