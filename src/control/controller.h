#pragma once
// What the tracking loop (tracking_loop.h) asks of a controller: every period, the commanded pressures from the
// desired wrist angles and the latest IMU reading. Controllers are plain objects with no plant and no clock, so
// the same object runs on the simulation and on the hardware bridge.

#include <array>
#include <string>

#include "control/plant.h"

namespace softwrist::control {

// Per axis (flexion/extension, ulnar/radial): whether the controller has found the desired angle out of reach.
using AxisFlags = std::array<bool, 2>;

class Controller {
 public:
  virtual ~Controller() = default;
  virtual std::string name() const = 0;
  // The loop period [s] the controller was designed for.
  virtual double period_s() const = 0;
  // Back to the state before the first command.
  virtual void reset() = 0;
  // One loop iteration at `t_s` (from the start of the run): the commanded pressures [kPa]. An invalid reading
  // must not move the pressures towards either limit.
  virtual Pressures command(double t_s, const Reference& desired, const ImuReading& reading) = 0;
  // The axes whose last desired angle the controller knows to be out of the exosuit's reach.
  virtual AxisFlags unreachable() const { return {false, false}; }
};

}  // namespace softwrist::control
