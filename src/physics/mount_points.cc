#include "physics/mount_points.h"

#include <cmath>

namespace softwrist::physics {
namespace {

Point2 towards(const Point2& from, const Point2& to, double distance) {
  const double length = std::hypot(to.x - from.x, to.y - from.y);
  if (!(length > 0.0)) return from;
  return {from.x + distance * (to.x - from.x) / length, from.y + distance * (to.y - from.y) / length};
}

}  // namespace

MountPoints mount_points(const Placement& placement, double joint_angle) {
  const double c = std::cos(joint_angle), s = std::sin(joint_angle);
  return {.forearm = {-placement.d1, placement.w1},
          .hand = {placement.d2 * c - placement.w2 * s, placement.d2 * s + placement.w2 * c}};
}

MountPoints stretched_mount_points(const Placement& placement, double wrist_radius, double joint_angle, double force,
                                   const MountStiffness& stiffness, WrapSurface surface) {
  const MountPoints mounts = mount_points(placement, joint_angle);
  if (!(force > 0.0)) return mounts;
  const MusclePath path = muscle_path(placement, wrist_radius, joint_angle, surface);
  Point2 forearm_target = mounts.hand, hand_target = mounts.forearm;
  if (path.regime == Regime::kWrapping) {  // towards the tangent points Q1 and Q2
    const TangentPoints q = tangent_points(placement, wrist_radius, surface, joint_angle, path);
    forearm_target = {q.q1x, q.q1y};
    hand_target = {q.q2x, q.q2y};
  }
  const MountStretches dx = mount_stretches(force, stiffness);
  return {.forearm = towards(mounts.forearm, forearm_target, dx.forearm),
          .hand = towards(mounts.hand, hand_target, dx.hand)};
}

Placement placement_from_mount_points(const MountPoints& points, double joint_angle) {
  const double c = std::cos(joint_angle), s = std::sin(joint_angle);
  // Rot(-joint_angle) P2.
  return {.d1 = -points.forearm.x,
          .w1 = points.forearm.y,
          .d2 = points.hand.x * c + points.hand.y * s,
          .w2 = -points.hand.x * s + points.hand.y * c};
}

}  // namespace softwrist::physics
