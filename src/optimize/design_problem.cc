#include "optimize/design_problem.h"

#include <algorithm>
#include <cmath>

#include "physics/errors.h"
#include "physics/fpam_force.h"

namespace softwrist::optimize {

void validate(const DesignProblem& problem) {
  using physics::InvalidParameter;
  if (problem.samples.angles.size() < 2 || problem.samples.angles.size() != problem.samples.torques.size()) {
    throw InvalidParameter("design problem: the reference needs at least two samples");
  }
  physics::require_positive("design pressure [Pa]", problem.pressure);
  physics::require_finite("max_stretch_angle [rad]", problem.max_stretch_angle);
  const auto& lo = problem.bounds.lower;
  const auto& hi = problem.bounds.upper;
  const auto check = [](const char* name, double lower, double upper) {
    physics::require_finite(name, lower);
    physics::require_finite(name, upper);
    if (lower > upper) throw InvalidParameter(std::string("bounds: ") + name + ": lower bound above upper bound");
  };
  check("d1", lo.d1, hi.d1);
  check("w1", lo.w1, hi.w1);
  check("d2", lo.d2, hi.d2);
  check("w2", lo.w2, hi.w2);
  // The corner nearest the wrist is the worst case for "both mounts outside the wrist circle".
  physics::validate(lo, problem.wrist_radius);
  (void)problem.fpam.at_pressure(problem.pressure);
  (void)physics::FpamForceLaw(problem.pressure, problem.fpam.at_pressure(problem.pressure), problem.fpam.fabric());
}

physics::Muscle design_muscle(const DesignProblem& problem, const physics::Placement& placement) {
  // L0 first: it can throw, and GCC 12 destroys a member twice when an exception leaves the aggregate
  // initialisation of a class with a base (Muscle's MuscleLaw).
  const double rest_length = physics::rest_length_for_range(placement, problem.wrist_radius, problem.max_stretch_angle);
  return physics::Muscle{{.fpam = problem.fpam, .rest_length = rest_length}, placement, problem.wrist_radius};
}

DesignEvaluator::DesignEvaluator(const DesignProblem& problem, double pressure)
    : problem_(problem), force_law_(pressure, problem.fpam.at_pressure(pressure), problem.fpam.fabric()) {
  validate(problem);
  for (double angle : problem.samples.angles) angles_.emplace_back(angle);
}

std::vector<double> DesignEvaluator::torque_curve(const physics::Placement& placement) const {
  const physics::Muscle muscle = design_muscle(problem_, placement);
  physics::validate(muscle);
  const physics::PlacementGeometry geometry(muscle.placement, muscle.wrist_radius);  // once for all the angles
  std::vector<double> torques;
  torques.reserve(angles_.size());
  for (const physics::JointAngle& angle : angles_)
    torques.push_back(physics::muscle_state(muscle, geometry, force_law_, angle).torque);
  return torques;
}

double DesignEvaluator::objective(const physics::Placement& placement) const {
  const std::vector<double> torques = torque_curve(placement);
  double sum = 0.0;
  for (std::size_t i = 0; i < torques.size(); ++i) {
    const double difference = problem_.samples.torques[i] - torques[i];
    sum += problem_.objective == DesignObjective::kDeficit ? std::max(0.0, difference) : std::abs(difference);
  }
  return sum;
}

double DesignEvaluator::max_deficit(const physics::Placement& placement) const {
  const std::vector<double> torques = torque_curve(placement);
  double worst = -INFINITY;
  for (std::size_t i = 0; i < torques.size(); ++i) worst = std::max(worst, problem_.samples.torques[i] - torques[i]);
  return worst;
}

}  // namespace softwrist::optimize
