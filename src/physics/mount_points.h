#pragma once
// Where the two mounts are, in the 2D frame of torque_geometry.h (O at the origin, x along the forearm): the
// paper's third torque method (Section Torque applied by the exosuit) takes the placement at each measurement from
// the motion-captured mount positions instead of the fixed initial placement. These functions give those
// positions for a placement whose mounts stretch (Eqn. fabric_stretching), and the placement back from measured
// positions.

#include "physics/mount_stretch.h"
#include "physics/torque_geometry.h"

namespace softwrist::physics {

struct Point2 {
  double x = 0.0;
  double y = 0.0;
};

struct MountPoints {
  Point2 forearm;  // P1
  Point2 hand;     // P2
};

// P1 = (-d1, w1) and P2 = Rot(joint_angle) (d2, w2).
MountPoints mount_points(const Placement& placement, double joint_angle);

// The mounts moved by Eqn. fabric_stretching at muscle force `force` [N]: each by sqrt(F/|K_i|) along the muscle's
// line of action towards the other end (towards the other mount when straight, towards its tangent point on the
// wrist when wrapped), as mount_stretch.h models it.
MountPoints stretched_mount_points(const Placement& placement, double wrist_radius, double joint_angle, double force,
                                   const MountStiffness& stiffness, WrapSurface surface = {});

// The placement whose mounts lie at `points` with the hand at `joint_angle` (the inverse of mount_points).
Placement placement_from_mount_points(const MountPoints& points, double joint_angle);

}  // namespace softwrist::physics
