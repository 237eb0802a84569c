#pragma once
// Antagonistic pairs (Section Design Overview): the flexor and extensor move flexion/extension, the ulnar and
// radial muscles ulnar/radial deviation. Each pair's net torque is the sum of its two muscles' torques
// (Section Torque applied by the exosuit: "the net torque can be approximated ... as the sum of the torques of
// antagonistic fPAMs").
//
// Sign convention for the wrist angles (used everywhere in softwrist): flexion positive, extension negative
// (as in Section Parameter optimization and Fig. ParameterOptimizationResult); ulnar deviation positive, radial
// negative. A muscle sees the joint angle in its own direction: the agonist (flexor, ulnar) sees +angle, the
// antagonist (extensor, radial) sees -angle, and its torque counts negative.

#include "physics/exosuit_layout.h"
#include "physics/muscle_torque.h"

namespace softwrist::physics {

struct AntagonisticPair {
  Muscle agonist;     // pulls towards positive angles: flexor or ulnar muscle
  Muscle antagonist;  // pulls towards negative angles: extensor or radial muscle
};

struct PairTorque {
  double net_torque = 0.0;  // [N m], positive towards flexion / ulnar deviation
  MuscleState agonist;
  MuscleState antagonist;
};

PairTorque pair_torque(const AntagonisticPair& pair, double joint_angle, double agonist_pressure,
                       double antagonist_pressure);

// The four muscles of the exosuit.
struct WristMuscles {
  AntagonisticPair flexion_extension;  // agonist flexor, antagonist extensor
  AntagonisticPair ulnar_radial;       // agonist ulnar, antagonist radial
  const AntagonisticPair& pair(WristAxis axis) const {
    return axis == WristAxis::kFlexionExtension ? flexion_extension : ulnar_radial;
  }
};

}  // namespace softwrist::physics
