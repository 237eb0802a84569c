#include "physics/muscle_law.h"

#include <cmath>
#include <optional>

#include "physics/errors.h"
#include "physics/plausible_ranges.h"

namespace softwrist::physics {

void validate(const MuscleLaw& law) {
  require_positive("rest_length L0 [m]", law.rest_length);
  require(law.rest_length <= plausible::kMaxLength, "rest_length L0 [m]", law.rest_length, "must be at most 10");
  if (law.stretch_mode != StretchMode::kNone) validate(law.mount_stiffness);
  validate_shape(law.mount_stiffness);  // a shape out of range is wrong whether or not the mounts stretch
}

namespace {

// The self-consistent stretch in closed form. Eqn. force is a quadratic in the fPAM's length l on each side of the
// elastic onset l_e = L0 (1 - epsilon_0): f(l) = a l^2 + b l + d. With l = L - c u and F = u^2 (mount_stretch.h),
// F = f(L - c u) is a quadratic in u: (a c^2 - 1) u^2 - c (2 a L + b) u + (a L^2 + b L + d) = 0, whose root in the
// piece's range of u is the one root of the strictly falling residual. The plugin evaluates this every step, where
// the iterative solver's eight or nine force evaluations were most of its cost (`softwrist bench sim`); nullopt
// where rounding leaves no root in range, for the iterative solver to settle.
std::optional<StretchedForce> closed_form_stretch(const MuscleLaw& law, const FpamForceLaw& force_law, double length,
                                                  const StretchConstants& constants) {
  const double rest = law.rest_length, c = constants.compliance, inverse_rest = constants.inverse_rest_length;
  const double onset_length = rest * (1.0 - force_law.elastic_onset());
  // Where the residual crosses zero: beyond u_e (l < l_e, no elastic term) or before it; at l_e the contraction
  // ratio is epsilon_0 itself.
  const double u_onset = length > onset_length ? (length - onset_length) * constants.inverse_compliance : 0.0;
  const bool elastic = length > onset_length && force_law(force_law.elastic_onset()) < u_onset * u_onset;
  if (elastic && !force_law.elastic_is_linear()) return std::nullopt;  // a J-shaped fabric: the iterative solve
  const FpamForceLaw::Quadratic q = force_law.quadratic(elastic);
  const double a = q.c2 * inverse_rest * inverse_rest, b = q.c1 * inverse_rest, d = q.c0;
  const double a2 = a * c * c - 1.0, a1 = -c * (2.0 * a * length + b), a0 = (a * length + b) * length + d;
  const double discriminant = a1 * a1 - 4.0 * a2 * a0;
  if (!(discriminant >= 0.0) || a2 == 0.0) return std::nullopt;
  const double half = -0.5 * (a1 + std::copysign(std::sqrt(discriminant), a1));  // no cancellation
  const double lo = elastic ? 0.0 : u_onset, hi = elastic ? u_onset : length * constants.inverse_compliance;
  for (const double u : {half / a2, half != 0.0 ? a0 / half : -1.0}) {
    if (u >= lo - 1e-12 * (1.0 + hi) && u <= hi + 1e-12 * (1.0 + hi) && u >= 0.0) return StretchedForce{u * u, c * u};
  }
  return std::nullopt;
}

}  // namespace

StretchConstants stretch_constants(const MuscleLaw& law) {
  const double compliance = mount_compliance(law.mount_stiffness);
  const bool closed_form = std::isfinite(compliance) && compliance > 0.0 && law.mount_stiffness.is_papers_law();
  return {compliance, closed_form ? 1.0 / compliance : 0.0, 1.0 / law.rest_length};
}

StretchedForce stretched_force(const MuscleLaw& law, const FpamForceLaw& force_law, double path_length) {
  return stretched_force(law, force_law, path_length, stretch_constants(law));
}

StretchedForce stretched_force(const MuscleLaw& law, const FpamForceLaw& force_law, double path_length,
                               const StretchConstants& constants) {
  // Eqn. force's contraction ratio (L0 - L) / L0 inline: L0 > 0 was validated, and the plugin's force must not
  // throw into MuJoCo.
  const auto force_at_length = [&](double length) {
    return force_law((law.rest_length - length) * constants.inverse_rest_length);
  };
  if (law.stretch_mode == StretchMode::kSelfConsistent && constants.inverse_compliance > 0.0 &&
      force_at_length(path_length) > 0.0) {
    if (auto solved = closed_form_stretch(law, force_law, path_length, constants)) return *solved;
  }
  return solve_mount_stretch(force_at_length, path_length, law.mount_stiffness, law.stretch_mode);
}

StretchedForce stretched_force(const MuscleLaw& law, double path_length, double pressure) {
  validate(law);
  return stretched_force(law, FpamForceLaw(pressure, law.fpam.at_pressure(pressure), law.fpam.fabric()), path_length);
}

}  // namespace softwrist::physics
