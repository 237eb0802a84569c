#pragma once
// The design problem of Section Parameter optimization: the placement (d1, w1, d2, w2) of one fPAM that brings its
// modeled torque up to a reference torque profile, with the fPAM (r0, eps_max), the pressure and the wrist radius
// fixed, and L0 "the shortest length that still allows the user to reach the full range of motion in the direction
// that stretches the muscle" (Eqn. length at that angle).

#include <vector>

#include "optimize/reference_torque.h"
#include "physics/exosuit_layout.h"
#include "physics/fpam_parameters.h"
#include "physics/muscle_torque.h"

namespace softwrist::optimize {

struct PlacementBounds {
  physics::Placement lower;
  physics::Placement upper;
};

// Table optimized_parameters: bounds for the paper's example user [m].
inline constexpr PlacementBounds kPaperBounds{.lower = {.d1 = 0.02, .w1 = 0.035, .d2 = 0.015, .w2 = 0.015},
                                              .upper = {.d1 = 0.22, .w1 = 0.05, .d2 = 0.09, .w2 = 0.035}};
// Table optimized_parameters: "Resolution for initial guesses" [m].
inline constexpr physics::Placement kPaperStartResolution{.d1 = 0.02, .w1 = 0.005, .d2 = 0.005, .w2 = 0.005};

enum class DesignObjective {
  kDeficit,        // Eqn. objective_function: sum of max(0, tau_ref - tau_mod), the paper's
  kAbsoluteError,  // sum of |tau_ref - tau_mod|: fit the profile rather than exceed it
};

struct DesignProblem {
  ReferenceTorque samples;  // the resampled reference (140 points in the paper)
  physics::FpamParameters fpam = physics::FpamParameters::Constant(0.0123, 0.28);
  double pressure = physics::kRegulatorMaxPressure;  // [Pa]
  double wrist_radius = 0.02;                        // r_w [m]
  double max_stretch_angle = 0.0;  // [rad], the angle (negative: towards extension for the flexor) that sets L0
  PlacementBounds bounds = kPaperBounds;
  DesignObjective objective = DesignObjective::kDeficit;
};

// Throws physics::InvalidParameter naming the problem: empty samples, lower > upper, a bound box with a placement
// whose mounts fall inside the wrist circle, a pressure or fPAM out of range.
void validate(const DesignProblem& problem);

// The muscle a placement gives: L0 from Eqn. length at max_stretch_angle, no mount stretching (the paper's design
// model).
physics::Muscle design_muscle(const DesignProblem& problem, const physics::Placement& placement);

// Evaluates placements at the problem's pressure with the force law prepared once.
class DesignEvaluator {
 public:
  explicit DesignEvaluator(const DesignProblem& problem, double pressure);
  explicit DesignEvaluator(const DesignProblem& problem) : DesignEvaluator(problem, problem.pressure) {}
  // The objective (DesignProblem::objective) at a placement inside the bounds [N m].
  double objective(const physics::Placement& placement) const;
  // The modeled torque at each sample angle [N m].
  std::vector<double> torque_curve(const physics::Placement& placement) const;
  // The largest tau_ref - tau_mod over the samples [N m]; <= 0 where the design meets the reference everywhere.
  double max_deficit(const physics::Placement& placement) const;

 private:
  const DesignProblem& problem_;
  physics::FpamForceLaw force_law_;
  std::vector<physics::JointAngle> angles_;  // the sample angles with their cosines and sines, worked out once
};

}  // namespace softwrist::optimize
