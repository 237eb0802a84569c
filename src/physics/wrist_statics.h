#pragma once
// The wrist the exosuit moves, seen statically (no inertia): the two antagonistic pairs, the relaxed wrist's
// stiffness, the hand's weight and the biological joint limits. One description shared by the range-of-motion
// statics (sim/wrist_statics.h), the model-based controller's feedforward and the reachability check (control/).
// Angles follow antagonistic_pair.h: flexion and ulnar deviation positive.

#include "physics/antagonistic_pair.h"
#include "physics/relaxed_wrist.h"

namespace softwrist::physics {

struct WristModel {
  WristMuscles muscles;
  double stiffness_fe = 0.0;  // relaxed wrist [N m/rad]
  double stiffness_ur = 0.0;
  double asymmetry_fe = 0.0;  // the relaxed wrist's stiffness asymmetry a (relaxed_wrist.h)
  double asymmetry_ur = 0.0;
  LimitStiffening limit_stiffening;  // the relaxed wrist stiffening towards the limits below (both axes)
  // m g c [N m]: the hand's weight about the ulnar/radial axis, pulling towards ulnar deviation with m g c cos(ur)
  // (the model's forearm lies with flexion/extension in the horizontal plane, so ulnar deviation lowers the hand);
  // 0 when a table carries the hand.
  double hand_weight_moment = 0.0;
  // Biological range of motion [rad], each positive: the joint stops.
  double flexion_limit = 0.0, extension_limit = 0.0, ulnar_limit = 0.0, radial_limit = 0.0;

  double stiffness(WristAxis axis) const { return axis == WristAxis::kFlexionExtension ? stiffness_fe : stiffness_ur; }
  double asymmetry(WristAxis axis) const { return axis == WristAxis::kFlexionExtension ? asymmetry_fe : asymmetry_ur; }
  // The joint stop in direction +1 (flexion, ulnar) or -1 (extension, radial), as a positive angle [rad].
  double limit(WristAxis axis, double direction) const;
  // The relaxed wrist's torque at `angle` [rad], positive towards flexion / ulnar deviation (relaxed_wrist.h).
  double passive(WristAxis axis, double angle) const;
};

// The static torques about one axis at `angle` [rad], each positive towards flexion / ulnar deviation [N m].
struct AxisTorques {
  double agonist = 0.0;     // flexor or ulnar muscle
  double antagonist = 0.0;  // extensor or radial muscle (<= 0)
  double passive = 0.0;     // the relaxed wrist (WristModel::passive)
  double gravity = 0.0;     // the hand's weight (ulnar/radial only)
  double net() const { return agonist + antagonist + passive + gravity; }
};

AxisTorques axis_torques(const WristModel& wrist, WristAxis axis, double angle, double agonist_pressure,
                         double antagonist_pressure);

// Where the wrist comes to rest when it starts at the neutral angle with these pressures [Pa] and moves in
// `direction` (+1 or -1): the first zero crossing of the net static torque, found by a 400-step scan up to the
// joint stop and bisection; the stop itself if the torque still pushes there; 0 if it does not push that way at
// neutral.
double settled_angle(const WristModel& wrist, WristAxis axis, double direction, double agonist_pressure,
                     double antagonist_pressure);

// The angles the exosuit can hold the relaxed wrist at (Section Range of motion): each muscle alone at the maximum
// pressure [Pa], its antagonist deflated.
struct ReachableRange {
  double flexion = 0.0, extension = 0.0, ulnar = 0.0, radial = 0.0;  // [rad], each positive
  // Whether `angle` [rad] on `axis` lies within the range, less `margin` [rad].
  bool contains(WristAxis axis, double angle, double margin = 0.0) const;
  // The angle [rad] nearest to `angle` within the range less `margin`; never past neutral when the margin exceeds
  // the range.
  double clamp(WristAxis axis, double angle, double margin = 0.0) const;
};
ReachableRange reachable_range(const WristModel& wrist, double max_pressure);

}  // namespace softwrist::physics
