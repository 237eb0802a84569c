#include "independent_device/muscle.h"

#include <algorithm>
#include <cmath>

#include "independent_device/units.h"

namespace softwrist::independent {

double effective_rest_length_m(const MuscleSpec& spec, const MuscleState& state) {
  return spec.rest_length_m *
         (1.0 + spec.creep_coefficient * std::log1p(state.pressure_time_s / spec.creep_reference_s));
}

namespace {

// A bracket [lo, hi] of the root of g(f) = F_muscle(f) - f: g(lo) > 0, g_hi = g(hi).
struct Bracket {
  double lo, g_lo, hi, g_hi;
};

// [0, f_high], where g(0) = f_high > 0 >= g(f_high); narrowed around `force_hint_n` when it lies inside.
template <typename G>
Bracket initial_bracket(G&& g, double f_high, double force_hint_n) {
  Bracket b{0.0, f_high, f_high, 0.0};
  if (force_hint_n > 0.0 && force_hint_n < f_high) {  // a narrow bracket around last step's tension
    const double delta = 1e-3 * force_hint_n + 1e-3;
    const double a = std::max(0.0, force_hint_n - delta), c = std::min(f_high, force_hint_n + delta);
    const double g_a = g(a);
    if (g_a <= 0.0) {
      b.hi = a;
      b.g_hi = g_a;
    } else {
      b.lo = a;
      b.g_lo = g_a;
      const double g_c = g(c);
      b.hi = c;
      b.g_hi = g_c;
      if (g_c > 0.0) {
        b.lo = c;
        b.g_lo = g_c;
        b.hi = f_high;
        b.g_hi = g(f_high);
      }
    }
    return b;
  }
  b.g_hi = g(f_high);
  return b;
}

// Illinois (modified regula falsi) on g within the bracket; its upper end when g vanishes there.
template <typename G>
double illinois_root(G&& g, Bracket b) {
  double lo = b.lo, g_lo = b.g_lo, hi = b.hi, g_hi = b.g_hi;
  double root = hi;
  if (g_hi < 0.0) {
    int side = 0;
    for (int iteration = 0; iteration < 200; ++iteration) {
      root = (lo * g_hi - hi * g_lo) / (g_hi - g_lo);
      const double g_root = g(root);
      if (std::abs(g_root) <= 1e-9 * (1.0 + root) || hi - lo <= 1e-12 * (1.0 + root)) break;
      if (g_root > 0.0) {
        lo = root;
        g_lo = g_root;
        if (side == 1) g_hi *= 0.5;
        side = 1;
      } else {
        hi = root;
        g_hi = g_root;
        if (side == -1) g_lo *= 0.5;
        side = -1;
      }
    }
  }
  return root;
}

}  // namespace

MuscleForce solve_muscle(const MuscleSpec& spec, const MuscleState& state, double theta_own_rad, double pressure_kpa,
                         double force_hint_n) {
  const double l0 = effective_rest_length_m(spec, state);
  const FpamAtPressure at = fpam_at_pressure(spec.law, std::max(0.0, pressure_kpa) * kPaPerKpa);
  const double friction = hysteresis_force_n(spec.hysteresis, state.hysteresis, at.area_force_n);
  const bool slides = spec.mount.glove_slide_m_per_n > 0.0;
  const Path fixed = muscle_path(spec.placement, spec.wrap, theta_own_rad, 0.0);
  const double root_compliance = mount_root_compliance(spec.mount);

  Path path = fixed;
  double contraction = 0.0;
  // Muscle tension when the mounts carry force f.
  auto evaluate = [&](double f) {
    if (slides) {
      const double slide = std::min(glove_slide_m(spec.mount, f), 0.5 * spec.placement.d2_m);
      path = muscle_path(spec.placement, spec.wrap, theta_own_rad, slide);
    }
    const double fabric_length = path.length_m - mount_takeup_m(spec.mount, root_compliance, f) - state.strap_slip_m;
    contraction = (l0 - fabric_length) / l0;
    const double static_force = fpam_force_n(spec.law, at, contraction);
    return static_force > 0.0 ? std::max(0.0, static_force + friction) : 0.0;
  };
  const auto g = [&](double f) { return evaluate(f) - f; };

  double root = 0.0;
  const double f_high = evaluate(0.0);
  if (f_high > 0.0) root = illinois_root(g, initial_bracket(g, f_high, force_hint_n));
  evaluate(root);  // path and contraction at the root
  MuscleForce out;
  out.force_n = root;
  out.torque_nm = root * path.moment_arm_m;
  out.contraction = contraction;
  out.muscle_length_m = l0 * (1.0 - contraction);
  out.wrapped = path.wrapped;
  return out;
}

MuscleForce solve_muscle_at_length(const MuscleSpec& spec, const MuscleState& state, double muscle_length_m,
                                   double pressure_kpa) {
  const double l0 = effective_rest_length_m(spec, state);
  const FpamAtPressure at = fpam_at_pressure(spec.law, std::max(0.0, pressure_kpa) * kPaPerKpa);
  const double friction = hysteresis_force_n(spec.hysteresis, state.hysteresis, at.area_force_n);
  MuscleForce out;
  out.contraction = (l0 - muscle_length_m) / l0;
  const double static_force = fpam_force_n(spec.law, at, out.contraction);
  out.force_n = static_force > 0.0 ? std::max(0.0, static_force + friction) : 0.0;
  out.muscle_length_m = muscle_length_m;
  return out;
}

void advance_muscle(const MuscleSpec& spec, MuscleState& state, const MuscleForce& solved, double pressure_kpa,
                    double dt_s) {
  if (state.has_length)
    hysteresis_advance(spec.hysteresis, state.hysteresis, solved.muscle_length_m - state.muscle_length_m);
  state.muscle_length_m = solved.muscle_length_m;
  state.has_length = true;
  state.pressure_time_s += dt_s * std::max(0.0, pressure_kpa) / kRegulatorMaxKpa;
  if (spec.slip_scale > 0.0) {
    const double target =
        spec.slip_scale * std::max(0.0, solved.force_n - spec.slip_threshold_n) / spec.slip_stiffness_n_per_m;
    state.strap_slip_m = std::max(state.strap_slip_m, target);
  }
}

}  // namespace softwrist::independent
