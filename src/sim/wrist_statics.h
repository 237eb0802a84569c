#pragma once
// The relaxed wrist's statics for one device (physics/wrist_statics.h): where one pressurised muscle holds the
// wrist once everything else that acts in the simulation is accounted for. It explains the difference between the
// paper's modeled joint limit (where the muscle's torque reaches zero, physics/range_of_motion.h) and where the
// simulated or real wrist settles.

#include "physics/wrist_statics.h"
#include "sim/device.h"

namespace softwrist::sim {

inline constexpr double kStandardGravity = 9.81;  // [m/s^2]

// The static description of a device's wrist; `gravity` [m/s^2] is 0 when a table carries the hand.
physics::WristModel wrist_model(const DeviceDescription& device, double gravity = kStandardGravity);

// The torques about a muscle's joint at `angle` [rad] in its own direction, positive in that direction [N m].
struct StaticTorques {
  double muscle = 0.0;      // the pressurised muscle (with the device's mount stretching)
  double antagonist = 0.0;  // its deflated antagonist's fabric elasticity (<= 0)
  double passive = 0.0;     // the relaxed wrist's stiffness (PassiveWrist)
  double gravity = 0.0;     // the hand's weight: ulnar/radial moves the hand in the vertical plane of the model
  double net() const { return muscle + antagonist + passive + gravity; }
};

StaticTorques static_torques(const DeviceDescription& device, MuscleIndex muscle, double pressure, double angle,
                             double gravity = kStandardGravity);

// The angle [rad, own direction] where the net static torque crosses zero between 0 and the joint's biological
// limit in that direction (the limit itself if the muscle still pushes there).
double settled_angle(const DeviceDescription& device, MuscleIndex muscle, double pressure,
                     double gravity = kStandardGravity);

}  // namespace softwrist::sim
