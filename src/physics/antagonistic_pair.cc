#include "physics/antagonistic_pair.h"

namespace softwrist::physics {

PairTorque pair_torque(const AntagonisticPair& pair, double joint_angle, double agonist_pressure,
                       double antagonist_pressure) {
  PairTorque result;
  result.agonist = muscle_state(pair.agonist, joint_angle, agonist_pressure);
  result.antagonist = muscle_state(pair.antagonist, -joint_angle, antagonist_pressure);
  result.net_torque = result.agonist.torque - result.antagonist.torque;
  return result;
}

}  // namespace softwrist::physics
