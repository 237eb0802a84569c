#pragma once
// One fPAM on the wrist: its description (Muscle) and the torque it applies at a joint angle and pressure
// (MuscleState), combining the muscle's length-to-force law (muscle_law.h: Eqn. force with the mounting-point
// stretching) and the path geometry (torque_geometry.h).

#include "physics/fpam_force.h"
#include "physics/muscle_law.h"
#include "physics/torque_geometry.h"

namespace softwrist::physics {

// Immutable description of one muscle of the exosuit: its length-to-force law (fPAM, L0, mounts) and where its
// path runs. Built as Muscle{{.fpam = ..., .rest_length = ...}, placement, wrist_radius}.
struct Muscle : MuscleLaw {
  Placement placement;
  double wrist_radius = 0.0;  // r_w [m]
  WrapSurface wrap_surface;   // the wrist surface's centre and shape (torque_geometry.h); the paper's: a circle at O
};
void validate(const Muscle& muscle);

struct MuscleState {
  Regime regime = Regime::kStraight;
  double path_length = 0.0;        // mount-to-mount length of the unstretched placement [m]
  double effective_length = 0.0;   // path_length minus the mounts' stretch [m]
  double contraction_ratio = 0.0;  // at the effective length
  double mount_stretch = 0.0;      // dx_1 + dx_2 [m]
  double force = 0.0;              // [N]
  double moment_arm = 0.0;         // [m]
  double torque = 0.0;             // [N m], positive in the muscle's own direction
};

// The muscle at `joint_angle` [rad] (positive in its own direction, see torque_geometry.h) and `pressure` [Pa].
MuscleState muscle_state(const Muscle& muscle, double joint_angle, double pressure);
// The same with the force law already prepared for one pressure from this muscle's fPAM, for loops over many angles
// or placements at that pressure (the design optimization). The muscle must have been validated.
MuscleState muscle_state(const Muscle& muscle, const FpamForceLaw& force_law, double joint_angle);
// The same with the placement's geometry worked out once (PlacementGeometry of the muscle's placement, r_w and
// centre).
MuscleState muscle_state(const Muscle& muscle, const PlacementGeometry& geometry, const FpamForceLaw& force_law,
                         const JointAngle& joint_angle);

// Section Parameter optimization: "the initial, fully stretched length of the fPAM should be the shortest length
// that still allows the user to reach the full range of motion in the direction that stretches the muscle",
// computed with Eqn. length at that angle (for example -65.4 deg for the paper's flexor).
double rest_length_for_range(const Placement& placement, double wrist_radius, double max_stretch_angle);

}  // namespace softwrist::physics
