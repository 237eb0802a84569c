#pragma once
// The fabric muscle's hysteresis as a state of its force: a muscle pulls harder while it is being stretched than while
// it shortens, at the same length and pressure (fPAM tensile tests, Naclerio & Hawkes, IEEE RA-L 5:3659, 2020; for
// McKibben muscles, Vo-Minh et al., IEEE/ASME Trans. Mechatronics 16:177, 2011). The state follows Dahl's
// rate-independent friction model (Dahl, "A solid friction model", Aerospace Corp. TOR-0158, 1968) with exponent 1:
//   ds/dt = (v - |v| s) / l_h,     force = static force (1 + h s),
// v the muscle's length rate (positive: being stretched). s moves towards +1 while the muscle lengthens and towards
// -1 while it shortens, over a length of the order of l_h, and holds while the muscle is still: a wrist held at an
// angle keeps the branch it came from. At h = 0 the force is the static law exactly (the paper's model, the default).

namespace softwrist::physics {

struct FpamHysteresis {
  double fraction = 0.0;             // h: half the loading-unloading force difference, relative; 0 <= h < 0.5
  double transition_length = 0.002;  // l_h [m]: the length change over which the branch turns (softwrist's choice:
                                     // 2 mm, a few percent of contraction on the paper's 32 cm muscle)
  bool active() const { return fraction > 0.0; }
};

// ds/dt [1/s] of the state `state` (in [-1, 1]) at the length rate `length_rate` [m/s].
double hysteresis_state_rate(const FpamHysteresis& hysteresis, double state, double length_rate);

// The force [N] on the branch `state` of the static force `static_force` [N]: static_force (1 + h s), s clamped to
// [-1, 1] (an explicit integrator may overshoot the bound by a step).
double hysteretic_force(const FpamHysteresis& hysteresis, double static_force, double state);

// Throws physics::InvalidParameter naming the field when h is outside [0, 0.5) or l_h is not positive.
void validate(const FpamHysteresis& hysteresis);

}  // namespace softwrist::physics
