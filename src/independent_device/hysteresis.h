#pragma once
// Friction inside the muscle: the bias-cut fibres scissor against each other and against the liner under a normal
// load that grows with pressure, so the tension depends on the loading history. The nominal fPAM has none (Naclerio
// & Hawkes 2020 report an absence of hysteresis). Forms of the `hysteresis` effect:
//  * Dahl (1968) friction state z in [-1, 1], dz/dx = (1 - z sgn(dx)) / x_c per unit of muscle lengthening x;
//    force F_c z with Coulomb level F_c = F_0 + mu pi r0^2 P (pressure-proportional dry friction of McKibben
//    muscles, Tondu & Lopez 2000).
//  * Maxwell-slip (Iwan 1966; applied to pneumatic muscles by Vo-Minh et al., IEEE/ASME T-Mech 16(1), 2011):
//    parallel elasto-slip elements with a spread of slip lengths, giving nested loops with non-local memory.
// Both are rate-independent, so a quasi-static rig can advance them along its path.

#include <array>

namespace softwrist::independent {

enum class HysteresisKind { none, dahl, maxwell_slip };

struct HysteresisLaw {
  HysteresisKind kind = HysteresisKind::none;
  double constant_n = 0.0;         // F_0: fabric's own friction
  double pressure_fraction = 0.0;  // mu: friction per unit of pi r0^2 P
  double length_m = 3e-3;          // x_c (Dahl) or the median slip length (Maxwell-slip)
};

inline constexpr std::size_t kSlipElements = 6;

struct HysteresisState {
  double z = 0.0;                            // Dahl state
  std::array<double, kSlipElements> slip{};  // Maxwell-slip element deflections, normalised to [-1, 1]
};

// Friction force added to the static tension [N]; area_force_n = pi r0^2 P.
double hysteresis_force_n(const HysteresisLaw& law, const HysteresisState& state, double area_force_n);
// Advances the state by a lengthening of the muscle [m] (negative: shortening). Exact for a monotone increment.
void hysteresis_advance(const HysteresisLaw& law, HysteresisState& state, double lengthening_m);

}  // namespace softwrist::independent
