#pragma once
// Generates the MuJoCo hand-forearm model (MJCF) from a device description.
//
// Frame of the forearm body (fixed to the world, turned so that flexion/extension happens in the horizontal plane
// as on the paper's torque rig and in Section Planar angle tracking): x along the forearm towards the hand, y
// radial, z dorsal. The hand hangs on two hinges at the joint centre O: wrist_fe about +y (flexion positive, hand
// towards palmar -z) and wrist_ur about -z (ulnar deviation positive, hand towards -y). Each muscle's 2D plane
// (torque_geometry.h) maps into 3D: the flexor lies in the x/-z half-plane, the extensor in x/+z, the ulnar muscle in
// x/-y, the radial in x/+y; its forearm mount is at (-d1, w1) and its hand mount at (d2, w2) in that plane, and it
// wraps around its own cylinder of radius r_w along its joint axis, on its own side (a sidesite).

#include <array>
#include <string>

#include "physics/exosuit_layout.h"
#include "sim/device.h"

namespace softwrist::sim {

// Each muscle's side in the forearm frame (its 2D y axis, torque_geometry.h), in kMuscleNames' order: the flexor
// palmar (-z), the extensor dorsal (+z), the ulnar muscle -y, the radial +y. The mounts and the drawing use it.
inline constexpr std::array<std::array<double, 3>, 4> kMuscleSides = {{{0, 0, -1}, {0, 0, 1}, {0, -1, 0}, {0, 1, 0}}};

enum class ActuatorKind {
  kFpamPlugin,  // <general> with user dynamics/gain/bias, configured for softwrist.fpam
  // MuJoCo's own <general> with force = ctrl on the same tendon, no dynamics: replays a recorded force (the plugin
  // benchmark's baseline, `softwrist bench sim`).
  kForceReplay,
};

struct ModelOptions {
  ActuatorKind actuators = ActuatorKind::kFpamPlugin;
  double timestep = 0.001;  // [s]
  // [m/s^2] along -z of the world; 0 when a table carries the hand (Section Planar angle tracking: the wrist moves
  // in the horizontal plane with the forearm on the table).
  double gravity = 9.81;
  // The wrist axis the hand's weight turns: ulnar/radial deviation (the frame above: forearm horizontal, thumb up),
  // or flexion/extension (the forearm turned palm down, so the weight flexes the wrist).
  physics::WristAxis gravity_axis = physics::WristAxis::kUlnarRadial;
  // The drawn hand, forearm, glove, band, IMUs and stand-offs (anatomy_visuals.h). They carry no mass and make no
  // contact; false leaves them out with their meshes, textures and materials and the table (a tenth of the compile
  // time: the diagnosis's replays, and the test that they change no dynamics).
  bool anatomy = true;
};

// The relaxed wrist's stiffening towards its limits (PassiveWrist::limit_stiffening), when it has any: a custom
// <numeric> "A s" ([N m], [rad]) that WristSim applies about both joints, towards their ranges' ends.
inline constexpr const char* kLimitStiffeningNumeric = "softwrist.limit_stiffening";
// Its stiffness asymmetry (PassiveWrist::stiffness_asymmetry_fe, _ur), when it has any: a custom <numeric> "a_fe a_ur"
// that WristSim applies as -k a |angle| about each joint, k the joint's stiffness.
inline constexpr const char* kStiffnessAsymmetryNumeric = "softwrist.stiffness_asymmetry";

// A muscle whose wrist surface is not a circle (physics::WrapSurface): MuJoCo wraps tendons around spheres and
// cylinders only, so its wrap cylinder stands for the surface's equivalent circle (torque_geometry.h: tangent to the
// same segments, the path as long), which WristSim moves before every step from the joint's angle. The custom
// <numeric> kWrapSurfaceNumeric + MUSCLE holds "d1 w1 d2 w2 r_w x y aspect" [m, m, m, m, m, m, m, -].
inline constexpr const char* kWrapSurfaceNumeric = "softwrist.wrap_surface:";

std::string build_model_xml(const DeviceDescription& device, const ModelOptions& options = {});

// `xml` (build_model_xml's) with dry friction of `friction_n` [N] on every muscle's tendon path (MuJoCo's tendon
// frictionloss: one constraint row per tendon, within the model's <size>): the muscles slide over the wrist against
// it. Not in the paper's model; the diagnosis's synthetic device uses it as an effect outside the catalogue.
std::string with_tendon_friction(std::string xml, double friction_n);

}  // namespace softwrist::sim
