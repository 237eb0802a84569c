#include "sim/wrist_statics.h"

#include <cmath>

#include "physics/muscle_torque.h"
#include "sim/wrist_sim.h"

namespace softwrist::sim {
namespace {

MuscleIndex antagonist_of(MuscleIndex muscle) {
  switch (muscle) {
    case kFlexor: return kExtensor;
    case kExtensor: return kFlexor;
    case kUlnar: return kRadial;
    case kRadial: return kUlnar;
  }
  return kFlexor;
}

double limit_in_direction(const DeviceDescription& device, MuscleIndex muscle) {
  switch (muscle) {
    case kFlexor: return device.wrist.flexion_limit;
    case kExtensor: return device.wrist.extension_limit;
    case kUlnar: return device.wrist.ulnar_limit;
    case kRadial: return device.wrist.radial_limit;
  }
  return 0.0;
}

}  // namespace

StaticTorques static_torques(const DeviceDescription& device, MuscleIndex muscle, double pressure, double angle,
                             double gravity) {
  StaticTorques t;
  t.muscle = physics::muscle_state(device.muscle(muscle), angle, pressure).torque;
  t.antagonist = -physics::muscle_state(device.muscle(antagonist_of(muscle)), -angle, 0.0).torque;
  const bool fe = joint_of(muscle) == WristJoint::kFlexionExtension;
  t.passive = -(fe ? device.wrist.stiffness_fe : device.wrist.stiffness_ur) * angle;
  // The model's forearm lies horizontal with flexion/extension in the horizontal plane (model_builder.h); ulnar
  // deviation lowers the hand, so its weight pulls towards ulnar with m g c cos(ur).
  if (!fe) {
    const double ur = direction_of(muscle) * angle;
    t.gravity = direction_of(muscle) * device.hand.mass * gravity * device.hand.com_distance * std::cos(ur);
  }
  return t;
}

double settled_angle(const DeviceDescription& device, MuscleIndex muscle, double pressure, double gravity) {
  const double limit = limit_in_direction(device, muscle);
  const auto net = [&](double angle) { return static_torques(device, muscle, pressure, angle, gravity).net(); };
  if (net(0.0) <= 0.0) return 0.0;
  const double step = limit / 400.0;
  double lo = 0.0;
  for (double hi = step; hi <= limit + 1e-12; hi += step) {
    if (net(hi) <= 0.0) {
      for (int i = 0; i < 60; ++i) {
        const double mid = 0.5 * (lo + hi);
        (net(mid) > 0.0 ? lo : hi) = mid;
      }
      return 0.5 * (lo + hi);
    }
    lo = hi;
  }
  return limit;
}

}  // namespace softwrist::sim
