#include "independent_device/muscle.h"

#include <algorithm>
#include <cmath>

#include "independent_device/units.h"

namespace softwrist::independent {

double effective_rest_length_m(const MuscleSpec& spec, const MuscleState& state) {
  return spec.rest_length_m *
         (1.0 + spec.creep_coefficient * std::log1p(state.pressure_time_s / spec.creep_reference_s));
}

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

  MuscleForce out;
  double root = 0.0;
  const double f_high = evaluate(0.0);
  if (f_high > 0.0) {
    // Illinois (modified regula falsi) on g(f) = F_muscle(f) - f, g(0) > 0 >= g(f_high).
    double lo = 0.0, g_lo = f_high, hi = f_high, g_hi = 0.0;
    bool bracketed = false;
    if (force_hint_n > 0.0 && force_hint_n < f_high) {  // a narrow bracket around last step's tension
      const double delta = 1e-3 * force_hint_n + 1e-3;
      const double a = std::max(0.0, force_hint_n - delta), b = std::min(f_high, force_hint_n + delta);
      const double g_a = evaluate(a) - a;
      if (g_a <= 0.0) {
        hi = a;
        g_hi = g_a;
      } else {
        lo = a;
        g_lo = g_a;
        const double g_b = evaluate(b) - b;
        hi = b;
        g_hi = g_b;
        if (g_b > 0.0) {
          lo = b;
          g_lo = g_b;
          hi = f_high;
          g_hi = evaluate(f_high) - f_high;
        }
      }
      bracketed = true;
    }
    if (!bracketed) g_hi = evaluate(f_high) - f_high;
    root = hi;
    if (g_hi < 0.0) {
      int side = 0;
      for (int iteration = 0; iteration < 200; ++iteration) {
        root = (lo * g_hi - hi * g_lo) / (g_hi - g_lo);
        const double g = evaluate(root) - root;
        if (std::abs(g) <= 1e-9 * (1.0 + root) || hi - lo <= 1e-12 * (1.0 + root)) break;
        if (g > 0.0) {
          lo = root;
          g_lo = g;
          if (side == 1) g_hi *= 0.5;
          side = 1;
        } else {
          hi = root;
          g_hi = g;
          if (side == -1) g_lo *= 0.5;
          side = -1;
        }
      }
    }
  }
  evaluate(root);  // path and contraction at the root
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
