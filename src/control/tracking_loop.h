#pragma once
// The loop that runs a controller on a plant along a desired trajectory (Fig. Control): every controller period,
// read the IMUs, ask the controller, command the regulators, wait. It only sees control::Plant, so a run on the
// simulation and a run on the hardware bridge are the same code.
//
// Zeroing (Sections Planar angle tracking and Spatial trajectory tracking: "the joint angles were set to zero at a
// neutral position of the wrist before starting the tracking"): the first valid reading, taken with the wrist at
// rest in its neutral position, is subtracted from every later one. That removes the IMU pair's mounting offset.
//
// Reachability: a target the exosuit cannot reach is reported rather than pushed at forever. An axis is flagged
// when the controller says so (Controller::unreachable), or when the muscle pulling towards the target has been at
// the regulator's maximum for `unreachable_dwell_s` while the error stayed above `unreachable_tolerance_deg`.

#include <functional>
#include <stdexcept>

#include "control/controller.h"
#include "control/trajectory.h"

namespace softwrist::control {

// A controller asked for a pressure outside the regulator range (or NaN) under OutOfRange::kStop.
class ControllerFault : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct TrackingOptions {
  // What a command outside [0, max] kPa or NaN means. The simulation clamps it, as the regulators would saturate.
  // A hardware trial stops instead: such a command is a controller bug, and next to a person's arm the plant is
  // vented and run_tracking throws ControllerFault naming the muscle and the value.
  enum class OutOfRange { kClamp, kStop };
  OutOfRange out_of_range = OutOfRange::kClamp;
  bool zero_at_start = true;
  // The pairs the controller drives; an inactive pair's muscles are vented (0 kPa), as in the paper's planar task
  // with two muscles.
  AxisFlags active_axes{true, true};
  double unreachable_tolerance_deg = 2.0;
  double unreachable_dwell_s = 1.0;
};

struct TrackingSample {
  double t_s = 0.0;  // from the start of the run
  Reference desired;
  ImuReading reading;   // zeroed
  Pressures command{};  // as sent to the plant (within its range)
  AxisFlags unreachable{false, false};
};

// Runs `trajectory` to its end (the controller is reset first); `on_tick` sees every iteration. The plant is vented
// at the end. Returns the number of iterations. Throws std::invalid_argument for bad options.
long run_tracking(Plant& plant, Controller& controller, const Trajectory& trajectory, const TrackingOptions& options,
                  const std::function<void(const TrackingSample&)>& on_tick);

}  // namespace softwrist::control
