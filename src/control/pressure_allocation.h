#pragma once
// Turning a torque demand on one axis into the pressures of its antagonistic pair, through the torque model
// (physics/wrist_statics.h). The Discussion's complaint about the paper's controller is that "the unit change of
// pressure causes a different change of the torque depending on the actual wrist angle"; going through the model
// makes the loop's gain a torque, whatever the angle.
//
// Co-contraction: at zero demand both muscles hold `co_contraction` (stiffness against disturbances, and no dead
// zone when the demand changes sign). Along one path parameter s in [-1, 1], the agonist of the demand's sign rises
// from co_contraction to the maximum while its antagonist falls from co_contraction to 0, so that at full demand
// the antagonist no longer fights (and the range is the exosuit's full range of motion). The pair's torque is
// monotone along s, so the demand is met by bisection.

#include "physics/wrist_statics.h"

namespace softwrist::control {

struct PairPressures {
  double agonist = 0.0;     // flexor or ulnar muscle [Pa]
  double antagonist = 0.0;  // extensor or radial muscle [Pa]
  // +1 when the demand exceeds what the pair can give towards positive angles at this angle, -1 towards negative
  // angles, 0 when it is met.
  int saturated = 0;
};

// The pressures along the co-contraction path at s in [-1, 1].
PairPressures pressures_on_path(double s, double co_contraction, double max_pressure);

// The pressures meeting `torque_demand` [N m, positive towards flexion / ulnar] of the muscles alone at `angle`
// [rad] on `axis`, within [0, max_pressure] [Pa].
PairPressures allocate_pair_pressures(const physics::WristModel& wrist, physics::WristAxis axis, double angle,
                                      double torque_demand, double co_contraction, double max_pressure);

}  // namespace softwrist::control
