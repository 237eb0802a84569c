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
//
// A strap of that shape in series with mounts that stretch as the paper's (a pre-tensioned band over the sleeve and
// the skin under it): the shaped law takes the share s of each mount's compliance at F_r, the paper's law the rest,
// dx_i = (1 - s) sqrt(F / |K_i|) + s sqrt(F_r / |K_i|) ((F - F_p)+ / F_r)^(1/n). s = 1 (the default) is the law above
// alone, s = 0 the paper's whatever the shape; at F_r (F_p = 0) the stretch is sqrt(F_r / |K_i|) for every s.
struct MountStiffness {
  double forearm = 0.0;
  double hand = 0.0;
  double exponent = 2.0;      // n, in [kMinMountExponent, kMaxMountExponent]
  double preload = 0.0;       // F_p [N], in [0, kMaxMountPreload]
  double shaped_share = 1.0;  // s, in [0, 1]
  // Whether the shaped law is the paper's square law (its shape, whatever its share).
  bool has_papers_shape() const { return exponent == 2.0 && preload == 0.0; }
  bool is_papers_law() const { return has_papers_shape() || shaped_share == 0.0; }
  // Whether the stretch is one power of the pull above one preload (the self-consistent solve's variable u below).
  bool is_one_law() const { return is_papers_law() || shaped_share == 1.0; }
};
// The shapes' range, the diagnosis's fit's too (so that a placement's own is never clamped there): from a linear band
// (n < 1 would be a mount that gives more the harder it is pulled, a strap tearing) to a J-curve that has all but
// locked; a preload up to 20 N, a fifth of the paper's largest pulls (above it the mounts would hardly move in a
// sweep).
inline constexpr double kMinMountExponent = 1.0;
inline constexpr double kMaxMountExponent = 5.0;
inline constexpr double kMaxMountPreload = 20.0;       // [N]
void validate(const MountStiffness& stiffness);        // K1, K2 and the shape
void validate_shape(const MountStiffness& stiffness);  // the exponent, the preload and the share only

// Eqn. fabric_stretching solved for one mount of stiffness K: dx = sqrt(F / |K|) [m]; with another `exponent` n and
// `preload` F_p [N], the law of MountStiffness.
double mount_stretch(double force, double stiffness, double exponent = 2.0, double preload = 0.0);
struct MountStretches {
  double forearm = 0.0;  // dx_1 [m]
  double hand = 0.0;     // dx_2 [m]
};
// dx_1 and dx_2 at force F, with MountStiffness's shaped share.
MountStretches mount_stretches(double force, const MountStiffness& stiffness);
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

// A bracket of the root of a decreasing residual: r_lo > 0 at lo, r_hi < 0 at hi.
struct RootBracket {
  double lo, r_lo, hi, r_hi;
};

// The root by the Illinois method (regula falsi that halves the stale end's residual, so that the bracket closes from
// both sides), at most 200 steps: the middle of the bracket once `narrow(lo, hi)`, or the step x where
// `converged(x, r)`.
template <class Residual, class Narrow, class Converged>
double illinois_root(const Residual& residual, RootBracket b, const Narrow& narrow, const Converged& converged) {
  int side = 0;
  for (int iteration = 0; iteration < 200 && !narrow(b.lo, b.hi); ++iteration) {
    const double x = (b.lo * b.r_hi - b.hi * b.r_lo) / (b.r_hi - b.r_lo);
    const double r = residual(x);
    if (converged(x, r)) return x;
    if (r > 0.0) {
      b.lo = x;
      b.r_lo = r;
      if (side == +1) b.r_hi *= 0.5;
      side = +1;
    } else {
      b.hi = x;
      b.r_hi = r;
      if (side == -1) b.r_lo *= 0.5;
      side = -1;
    }
  }
  return 0.5 * (b.lo + b.hi);
}

template <class ForceAtLength>
StretchedForce solve_mixed_mount_stretch(const ForceAtLength& force_at_length, double path_length,
                                         const MountStiffness& stiffness, StretchMode mode);

// The force of a muscle whose mounts stretch. `force_at_length(L)` is the fPAM force law at path length L
// (non-decreasing in L); `path_length` the mount-to-mount path length of the unstretched placement.
template <class ForceAtLength>
StretchedForce solve_mount_stretch(const ForceAtLength& force_at_length, double path_length,
                                   const MountStiffness& stiffness, StretchMode mode) {
  const double unstretched = force_at_length(path_length);
  if (mode == StretchMode::kNone || unstretched <= 0.0) return {unstretched, 0.0};
  validate(stiffness);
  if (!stiffness.is_one_law()) return solve_mixed_mount_stretch(force_at_length, path_length, stiffness, mode);
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
  // Self-consistent to 1e-13 of the force: done, without waiting for the far end of the bracket to close.
  const double u = illinois_root(
      residual, {lo, r_lo, hi, r_hi}, [](double a, double b) { return b - a <= 1e-12 * (1.0 + b); },
      [&](double x, double r) { return std::abs(r) <= 1e-13 * take_up.force(x); });
  return {take_up.force(u), k * u};
}

// A shaped strap in series with the paper's law (0 < s < 1, validated): the stretch is no power of one variable, so the
// self-consistent root of residual(F) = f(L - stretch(F)) - F, decreasing in F, is bracketed on [f(L - stretch(f(L))),
// f(L)] and solved in F by the Illinois method.
template <class ForceAtLength>
StretchedForce solve_mixed_mount_stretch(const ForceAtLength& force_at_length, double path_length,
                                         const MountStiffness& stiffness, StretchMode mode) {
  auto force_with_stretch = [&](double stretch) {
    return force_at_length(path_length > stretch ? path_length - stretch : 0.0);
  };
  const double unstretched = force_at_length(path_length);
  const double one_shot_stretch = total_mount_stretch(unstretched, stiffness);
  if (mode == StretchMode::kOneShot) return {force_with_stretch(one_shot_stretch), one_shot_stretch};
  auto residual = [&](double f) { return force_with_stretch(total_mount_stretch(f, stiffness)) - f; };
  const double hi = unstretched, r_hi = residual(hi);
  if (r_hi >= 0.0) return {hi, total_mount_stretch(hi, stiffness)};  // the stretch costs no force
  const double lo = force_with_stretch(one_shot_stretch);            // the pull at the most stretch: below the root
  const double r_lo = residual(lo);
  if (r_lo <= 0.0) return {lo, total_mount_stretch(lo, stiffness)};
  const double f = illinois_root(
      residual, {lo, r_lo, hi, r_hi}, [](double a, double b) { return b - a <= 1e-13 * b; },
      [](double x, double r) { return std::abs(r) <= 1e-13 * x; });
  return {f, total_mount_stretch(f, stiffness)};
}

}  // namespace softwrist::physics
