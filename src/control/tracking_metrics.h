#pragma once
// The tracking figures of Section Control and Demonstration, from a recorded run (simulated, imported or from the
// hardware): the step response of one step (rise time and overshoot, as in Section Planar angle tracking) and the
// root mean square error along a trajectory (Section Spatial trajectory tracking).

#include <span>

namespace softwrist::control {

struct StepResponse {
  double rise_time_s = 0.0;      // 10 % to 90 % of the step; NaN when the angle never reaches 90 %
  double overshoot_pct = 0.0;    // the largest excursion past the target, in % of the step (0 if none)
  double final_error_deg = 0.0;  // mean (angle - target) over the last `final_window_s` of the segment
};

struct StepResponseOptions {
  double smoothing_s = 0.05;  // centred moving average against IMU noise before the crossings and the peak
  double final_window_s = 2.0;
};

// One step from `from_deg` to `to_deg` (they differ), with the samples `t_s` (increasing, starting at the step)
// and `angle_deg` of its segment. Throws std::invalid_argument for mismatched or empty samples.
StepResponse step_response(std::span<const double> t_s, std::span<const double> angle_deg, double from_deg,
                           double to_deg, const StepResponseOptions& options = {});

// sqrt(mean((actual - desired)^2)); NaN for no samples.
double rms_error(std::span<const double> desired, std::span<const double> actual);

}  // namespace softwrist::control
