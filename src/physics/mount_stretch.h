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
//    u = sqrt(F) (where the residual is smooth; u = ((F - F_p)+)^(1/n) for MountStiffness's other shapes) by the
//    Illinois false-position method; with the paper's law and the fPAM's own force law, which is quadratic in length
//    on each side of the elastic onset, stretched_force solves it in closed form instead (muscle_law.cc), tested
//    against this solver.
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

// The pull at which a mount law of another shape stretches as the paper's with the same K (below) [N]: the
// geometric middle of the torque sweeps' pulls (about 10 to 100 N: the paper's 3.3 N m peak over moment arms of 3-4
// cm). A choice of parameterisation, not a physical parameter: any value spans the same laws, but near the typical
// pull K and the exponent do not trade against each other in a fit.
inline constexpr double kMountReferenceForce = 30.0;

// Stretching coefficients K_1 (forearm) and K_2 (hand) of Eqn. fabric_stretching [N/m^2], and the law's shape.
//
// Beyond the paper (for straps and gloves whose take-up is not quadratic): dx_i = sqrt(F_r / |K_i|) ((F - F_p)+ /
// F_r)^(1/n), F_r = kMountReferenceForce. n = 2 with F_p = 0 is Eqn. fabric_stretching (for any F_r); n = 1 a linear
// elastic band, n > 2 a fabric that stiffens as it is pulled (the J-curve of woven straps and soft tissue); F_p a
// strap pre-tensioned on donning, which gives only once the muscle pulls harder than it. K_i keeps its unit and,
// at F_r, its stretch.
struct MountStiffness {
  double forearm = 0.0;
  double hand = 0.0;
  double exponent = 2.0;  // n, in [kMinMountExponent, kMaxMountExponent]
  double preload = 0.0;   // F_p [N], in [0, kMaxMountPreload]
  bool is_papers_law() const { return exponent == 2.0 && preload == 0.0; }
};
// The shapes' range, the diagnosis's fit's too (so that a placement's own is never clamped there): from a linear band
// (n < 1 would be a mount that gives more the harder it is pulled, a strap tearing) to a J-curve that has all but
// locked; a preload up to 20 N, a fifth of the paper's largest pulls (above it the mounts would hardly move in a
// sweep).
inline constexpr double kMinMountExponent = 1.0;
inline constexpr double kMaxMountExponent = 5.0;
inline constexpr double kMaxMountPreload = 20.0;       // [N]
void validate(const MountStiffness& stiffness);        // K1, K2 and the shape
void validate_shape(const MountStiffness& stiffness);  // the exponent and the preload only

// Eqn. fabric_stretching solved for one mount of stiffness K: dx = sqrt(F / |K|) [m]; with another `exponent` n and
// `preload` F_p [N], the law of MountStiffness.
double mount_stretch(double force, double stiffness, double exponent = 2.0, double preload = 0.0);
// dx_1 + dx_2 [m] at force F.
double total_mount_stretch(double force, const MountStiffness& stiffness);
// c = 1/sqrt|K_1| + 1/sqrt|K_2| [m/sqrt(N)]: the total stretch of the paper's law is c sqrt(F).
inline double mount_compliance(const MountStiffness& stiffness) {
  return 1.0 / std::sqrt(std::abs(stiffness.forearm)) + 1.0 / std::sqrt(std::abs(stiffness.hand));
}

// The mounts' law in the variable the self-consistent solve runs in, u = ((F - F_p)+)^(1/n): the total stretch
// k u is linear in it, and f(L - k u) - F(u) smooth where the stretch's slope in F is infinite (n > 1 at F_p).
struct MountTakeUp {
  double per_unit = 0.0;  // k = c sqrt(F_r) F_r^(-1/n) [m N^(-1/n)]; c for the paper's law
  double exponent = 2.0;
  double preload = 0.0;
  double force(double u) const { return preload + (exponent == 2.0 ? u * u : std::pow(u, exponent)); }
  double unit(double force) const {
    const double excess = force - preload;
    if (excess <= 0.0) return 0.0;
    return exponent == 2.0 ? std::sqrt(excess) : std::pow(excess, 1.0 / exponent);
  }
};
MountTakeUp mount_take_up(const MountStiffness& stiffness);

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
  const MountTakeUp take_up = mount_take_up(stiffness);
  if (unstretched <= take_up.preload) return {unstretched, 0.0};  // the mounts give only above their preload
  const double k = take_up.per_unit;
  auto force_with_stretch = [&](double stretch) {
    return force_at_length(path_length > stretch ? path_length - stretch : 0.0);
  };
  if (mode == StretchMode::kOneShot) {
    const double stretch = k * take_up.unit(unstretched);
    return {force_with_stretch(stretch), stretch};
  }
  // Self-consistent: root of residual(u) = f(L - k u) - F(u), decreasing in u, on [0, u(f(L))].
  // g(u) = u(f(L - k u)) is decreasing, so g(hi) is a lower bound of the root and g(g(hi)) an upper one:
  // two evaluations that narrow the bracket far more than regula falsi's first steps would.
  auto residual = [&](double u) { return force_with_stretch(k * u) - take_up.force(u); };
  double hi = take_up.unit(unstretched);
  const double f_hi = force_with_stretch(k * hi);
  double r_hi = f_hi - take_up.force(hi);
  if (r_hi >= 0.0) return {take_up.force(hi), k * hi};  // f(L - s) == f(L): the stretch costs no force
  double lo = take_up.unit(f_hi);
  const double f_lo = force_with_stretch(k * lo);
  double r_lo = f_lo - take_up.force(lo);
  if (const double upper = take_up.unit(f_lo); upper < hi && upper > lo) {
    const double r_upper = residual(upper);
    if (r_upper <= 0.0) hi = upper, r_hi = r_upper;
  }
  if (r_lo <= 0.0) return {take_up.force(lo), k * lo};  // the lower bound is the root (to rounding)
  int side = 0;
  for (int iteration = 0; iteration < 200 && hi - lo > 1e-12 * (1.0 + hi); ++iteration) {
    const double u = (lo * r_hi - hi * r_lo) / (r_hi - r_lo);
    const double r = residual(u);
    // Self-consistent to 1e-13 of the force: done, without waiting for the far end of the bracket to close.
    if (std::abs(r) <= 1e-13 * take_up.force(u)) {
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
  return {take_up.force(u), k * u};
}

}  // namespace softwrist::physics
