#pragma once
// Stretching of the mounting points (Section Torque applied by the exosuit, Eqn. fabric_stretching):
// F = K_i dx_i^2, i = 1 (forearm), 2 (hand), dx_i the displacement of mount i in the direction of the force.
//
// Geometric effect: each mount moves along the muscle's own line of action towards the other end (along P1P2 when
// straight, along its tangent to the wrist when wrapped). That leaves the line of action, and so the moment arm,
// unchanged and shortens the muscle by dx_1 + dx_2. Stretching therefore acts as an effective length
// L - dx_1 - dx_2 at the same moment arm; being shorter, the fPAM is more contracted and pulls less.
//
// Two versions:
//  - kOneShot (the paper's): F is "the force applied by the fPAM at the endpoints using the initial placement
//    parameters", dx_i = sqrt(F/K_i), and the force is then evaluated once at the shortened length.
//  - kSelfConsistent: the force and the stretch agree, F = f(L - dx_1(F) - dx_2(F)). The residual
//    f(L - c sqrt(F)) - F falls strictly with F, so the fixed point is unique; it is bracketed and solved in
//    u = sqrt(F) (where the residual is smooth) by the Illinois false-position method; with the fPAM's own force law,
//    which is quadratic in length on each side of the elastic onset, stretched_force solves it in closed form
//    instead (muscle_law.cc), tested against this solver.
//
// Sign of K: Table torque_measurement_parameters prints K1 = -43.36 and K2 = -1097.50 N/cm^2. With F >= 0 and
// dx^2 >= 0, F = K dx^2 has no solution for K < 0, so the sign cannot be the stiffness's; it matches the paper
// measuring each displacement against the force direction. Only |K| enters, and a zero K is rejected.

#include <cmath>
#include <optional>
#include <string_view>

#include "physics/errors.h"

namespace softwrist::physics {

enum class StretchMode { kNone, kOneShot, kSelfConsistent };
const char* to_string(StretchMode mode);
// "none", "oneshot" or "selfconsistent"; nullopt for anything else.
std::optional<StretchMode> parse_stretch_mode(std::string_view name);

// Stretching coefficients K_1 (forearm) and K_2 (hand) of Eqn. fabric_stretching [N/m^2].
struct MountStiffness {
  double forearm = 0.0;
  double hand = 0.0;
};
void validate(const MountStiffness& stiffness);

// Eqn. fabric_stretching solved for one mount: dx = sqrt(F / |K|) [m].
double mount_stretch(double force, double stiffness);
// dx_1 + dx_2 [m] at force F.
double total_mount_stretch(double force, const MountStiffness& stiffness);
// c = 1/sqrt|K_1| + 1/sqrt|K_2| [m/sqrt(N)]: the total stretch is c sqrt(F).
inline double mount_compliance(const MountStiffness& stiffness) {
  return 1.0 / std::sqrt(std::abs(stiffness.forearm)) + 1.0 / std::sqrt(std::abs(stiffness.hand));
}

struct StretchedForce {
  double force = 0.0;          // the fPAM's pull with the mounts stretched [N]
  double mount_stretch = 0.0;  // dx_1 + dx_2 [m]
};

// The force of a muscle whose mounts stretch. `force_at_length(L)` is the fPAM force law at path length L
// (non-decreasing in L); `path_length` the mount-to-mount path length of the unstretched placement.
template <class ForceAtLength>
StretchedForce solve_mount_stretch(const ForceAtLength& force_at_length, double path_length,
                                   const MountStiffness& stiffness, StretchMode mode) {
  const double unstretched = force_at_length(path_length);
  if (mode == StretchMode::kNone || unstretched <= 0.0) return {unstretched, 0.0};
  validate(stiffness);
  const double compliance = mount_compliance(stiffness);
  auto force_with_stretch = [&](double stretch) {
    return force_at_length(path_length > stretch ? path_length - stretch : 0.0);
  };
  if (mode == StretchMode::kOneShot) {
    const double stretch = compliance * std::sqrt(unstretched);
    return {force_with_stretch(stretch), stretch};
  }
  // Self-consistent: root of residual(u) = f(L - compliance u) - u^2, decreasing in u, on [0, sqrt(f(L))].
  // g(u) = sqrt(f(L - compliance u)) is decreasing, so g(hi) is a lower bound of the root and g(g(hi)) an upper one:
  // two evaluations that narrow the bracket far more than regula falsi's first steps would.
  auto residual = [&](double u) { return force_with_stretch(compliance * u) - u * u; };
  double hi = std::sqrt(unstretched);
  const double f_hi = force_with_stretch(compliance * hi);
  double r_hi = f_hi - hi * hi;
  if (r_hi >= 0.0) return {hi * hi, compliance * hi};  // f(L - s) == f(L): the stretch costs no force
  double lo = std::sqrt(std::max(0.0, f_hi));
  const double f_lo = force_with_stretch(compliance * lo);
  double r_lo = f_lo - lo * lo;
  if (const double upper = std::sqrt(std::max(0.0, f_lo)); upper < hi && upper > lo) {
    const double r_upper = residual(upper);
    if (r_upper <= 0.0) hi = upper, r_hi = r_upper;
  }
  if (r_lo <= 0.0) return {lo * lo, compliance * lo};  // the lower bound is the root (to rounding)
  int side = 0;
  for (int iteration = 0; iteration < 200 && hi - lo > 1e-12 * (1.0 + hi); ++iteration) {
    const double u = (lo * r_hi - hi * r_lo) / (r_hi - r_lo);
    const double r = residual(u);
    // Self-consistent to 1e-13 of the force: done, without waiting for the far end of the bracket to close.
    if (std::abs(r) <= 1e-13 * u * u) {
      lo = hi = u;
      break;
    }
    if (r > 0.0) {
      lo = u;
      r_lo = r;
      if (side == +1) r_hi *= 0.5;  // Illinois: halve the stale end so the bracket closes from both sides
      side = +1;
    } else {
      hi = u;
      r_hi = r;
      if (side == -1) r_lo *= 0.5;
      side = -1;
    }
  }
  const double u = 0.5 * (lo + hi);
  return {u * u, compliance * u};
}

}  // namespace softwrist::physics
