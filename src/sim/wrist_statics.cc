#include "sim/wrist_statics.h"

#include "sim/wrist_sim.h"

namespace softwrist::sim {
physics::WristModel wrist_model(const DeviceDescription& device, double gravity) {
  return {.muscles = {.flexion_extension = {.agonist = device.muscle(kFlexor), .antagonist = device.muscle(kExtensor)},
                      .ulnar_radial = {.agonist = device.muscle(kUlnar), .antagonist = device.muscle(kRadial)}},
          .stiffness_fe = device.wrist.stiffness_fe,
          .stiffness_ur = device.wrist.stiffness_ur,
          .asymmetry_fe = device.wrist.stiffness_asymmetry_fe,
          .asymmetry_ur = device.wrist.stiffness_asymmetry_ur,
          .limit_stiffening = device.wrist.limit_stiffening,
          .hand_weight_moment = device.hand.mass * gravity * device.hand.com_distance,
          .flexion_limit = device.wrist.flexion_limit,
          .extension_limit = device.wrist.extension_limit,
          .ulnar_limit = device.wrist.ulnar_limit,
          .radial_limit = device.wrist.radial_limit};
}

StaticTorques static_torques(const DeviceDescription& device, MuscleIndex muscle, double pressure, double angle,
                             double gravity) {
  const double direction = physics::direction_of(muscle);
  const bool agonist = direction > 0.0;
  const physics::AxisTorques t =
      physics::axis_torques(wrist_model(device, gravity), physics::axis_of(muscle), direction * angle,
                            agonist ? pressure : 0.0, agonist ? 0.0 : pressure);
  return {.muscle = direction * (agonist ? t.agonist : t.antagonist),
          .antagonist = direction * (agonist ? t.antagonist : t.agonist),
          .passive = direction * t.passive,
          .gravity = direction * t.gravity};
}

double settled_angle(const DeviceDescription& device, MuscleIndex muscle, double pressure, double gravity) {
  const double direction = physics::direction_of(muscle);
  const bool agonist = direction > 0.0;
  return direction * physics::settled_angle(wrist_model(device, gravity), physics::axis_of(muscle), direction,
                                            agonist ? pressure : 0.0, agonist ? 0.0 : pressure);
}

}  // namespace softwrist::sim
