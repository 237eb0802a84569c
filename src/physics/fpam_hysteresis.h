#pragma once
// The fabric muscle's hysteresis as a state of its force: a muscle pulls harder while it is being stretched than while
// it shortens, at the same length and pressure (fPAM tensile tests, Naclerio & Hawkes, IEEE RA-L 5:3659, 2020; for
// McKibben muscles, Vo-Minh et al., IEEE/ASME Trans. Mechatronics 16:177, 2011). The state follows Dahl's
// rate-independent friction model (Dahl, "A solid friction model", Aerospace Corp. TOR-0158, 1968) with exponent 1:
//   ds/dt = (v - |v| s) / l_h,     force = F + s (h F + min(F, F_0 + mu pi r0^2 P)),
// v the muscle's length rate (positive: being stretched), F the static force. s moves towards +1 while the muscle
// lengthens and towards -1 while it shortens, over a length of the order of l_h, and holds while the muscle is still:
// a wrist held at an angle keeps the branch it came from. The loop's half width has a part that scales with the pull
// (h F: the bladder and fibres slide under the tension) and a dry friction whose level grows with the pressure that
// presses the fibres together (F_0 + mu pi r0^2 P: Tondu & Lopez, IEEE Control Syst. Mag. 20(2):15, 2000, for
// McKibben muscles; Davis & Caldwell, Int. J. Robot. Res. 25:359, 2006, for braid friction). The dry friction is
// bounded by the pull itself, so a slack muscle pulls nothing on either branch. All zero (the default) is the
// paper's static law exactly.

#include <optional>
#include <string>

namespace softwrist::physics {

struct FpamHysteresis {
  double fraction = 0.0;             // h: the part of the loop's half width proportional to the pull; 0 <= h < 0.5
  double friction_force = 0.0;       // F_0 [N]: dry friction of the fabric at 0 kPa
  double pressure_friction = 0.0;    // mu: dry friction per newton of pi r0^2 P (the pressure's end force)
  double transition_length = 0.002;  // l_h [m]: the length change over which the branch turns (softwrist's choice:
                                     // 2 mm, a few percent of contraction on the paper's 32 cm muscle)
  bool active() const { return fraction > 0.0 || friction_force > 0.0 || pressure_friction > 0.0; }
};

// ds/dt [1/s] of the state `state` (in [-1, 1]) at the length rate `length_rate` [m/s].
double hysteresis_state_rate(const FpamHysteresis& hysteresis, double state, double length_rate);

// The force [N] on the branch `state` of the static force `static_force` [N] (above), with `pressure_end_force` =
// pi r0^2 P [N]; s clamped to [-1, 1] (an explicit integrator may overshoot the bound by a step), never negative.
double hysteretic_force(const FpamHysteresis& hysteresis, double static_force, double state, double pressure_end_force);

// The state after the muscle lengthens by `lengthening` [m] (negative: shortens) from `state`, monotonically: Dahl's
// closed form s = sgn(x) + (s0 - sgn(x)) exp(-|x| / l_h). For rigs that move in steps (the tensile test).
double hysteresis_state_after(const FpamHysteresis& hysteresis, double state, double lengthening);

// The fields of FpamHysteresis, for readers that name them their own way (the plugin's attributes, the placement
// file): one range check, worded once.
enum class HysteresisField { kFraction, kFrictionForce, kPressureFriction, kTransitionLength };
struct HysteresisProblem {
  HysteresisField field;
  double value;
  std::string requirement;  // "must be >= 0 and < 0.5"
};

// The first field outside its range: h outside [0, 0.5), F_0 negative, mu outside [0, 1), l_h not positive (or any
// of them not finite); nullopt when all are within.
std::optional<HysteresisProblem> hysteresis_problem(const FpamHysteresis& hysteresis);

// Throws physics::InvalidParameter naming the field by its plugin attribute (hysteresis, hysteresis_friction,
// hysteresis_pressure_friction, hysteresis_length) on hysteresis_problem's first finding.
void validate(const FpamHysteresis& hysteresis);

}  // namespace softwrist::physics
