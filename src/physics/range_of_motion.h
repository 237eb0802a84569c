#pragma once
// The modeled joint limit of one muscle acting alone (Section Range of motion): "the wrist angle where the modeled
// torque reached zero", with the torque estimated from 0 to 90 deg in the muscle's own direction.

#include <optional>

#include "physics/muscle_torque.h"

namespace softwrist::physics {

// The smallest angle in [0, max_angle] [rad] at which the muscle's torque at `pressure` [Pa] has fallen to zero,
// found by a 0.5-degree scan and bisection to 1e-10 rad. 0 when the muscle applies no torque at the neutral
// wrist already; nullopt when its torque stays positive up to max_angle.
std::optional<double> joint_limit(const Muscle& muscle, double pressure, double max_angle);

}  // namespace softwrist::physics
