#include "physics/muscle_torque.h"

#include "physics/errors.h"
#include "physics/fpam_force.h"

namespace softwrist::physics {

void validate(const Muscle& muscle) {
  validate(muscle.placement, muscle.wrist_radius, muscle.wrap_surface);
  validate(static_cast<const MuscleLaw&>(muscle));
}

MuscleState muscle_state(const Muscle& muscle, double joint_angle, double pressure) {
  validate(muscle);
  return muscle_state(muscle, FpamForceLaw(pressure, muscle.fpam.at_pressure(pressure), muscle.fpam.fabric()),
                      joint_angle);
}

MuscleState muscle_state(const Muscle& muscle, const FpamForceLaw& force_law, double joint_angle) {
  return muscle_state(muscle, PlacementGeometry(muscle.placement, muscle.wrist_radius, muscle.wrap_surface), force_law,
                      JointAngle(joint_angle));
}

MuscleState muscle_state(const Muscle& muscle, const PlacementGeometry& geometry, const FpamForceLaw& force_law,
                         const JointAngle& joint_angle) {
  const MusclePath path = geometry.at(joint_angle);
  const StretchedForce stretched = stretched_force(muscle, force_law, path.length);

  MuscleState state;
  state.regime = path.regime;
  state.path_length = path.length;
  state.mount_stretch = stretched.mount_stretch;
  state.effective_length = path.length > stretched.mount_stretch ? path.length - stretched.mount_stretch : 0.0;
  // contraction_ratio() inline: L0 > 0 is the validated law's, and the effective length is non-negative by
  // construction.
  state.contraction_ratio = (muscle.rest_length - state.effective_length) / muscle.rest_length;
  state.force = stretched.force;
  state.moment_arm = path.moment_arm;
  state.torque = stretched.force * path.moment_arm;
  return state;
}

double rest_length_for_range(const Placement& placement, double wrist_radius, double max_stretch_angle) {
  return muscle_path(placement, wrist_radius, max_stretch_angle).length;
}

}  // namespace softwrist::physics
