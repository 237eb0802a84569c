#include "control/tracking_loop.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

namespace softwrist::control {
namespace {

// The "pushing at the limit without getting there" watch of one axis.
class ReachWatch {
 public:
  ReachWatch(double tolerance_deg, double dwell_s) : tolerance_deg_(tolerance_deg), dwell_s_(dwell_s) {}
  bool update(double t_s, double error_deg, double positive_kpa, double negative_kpa, double max_kpa) {
    constexpr double kAtLimitKpa = 0.5;
    const double pulling = error_deg > 0.0 ? positive_kpa : negative_kpa;
    const bool stuck = std::abs(error_deg) > tolerance_deg_ && pulling >= max_kpa - kAtLimitKpa;
    if (!stuck)
      since_ = -1.0;
    else if (since_ < 0.0)
      since_ = t_s;
    return stuck && t_s - since_ >= dwell_s_;
  }

 private:
  double tolerance_deg_, dwell_s_;
  double since_ = -1.0;
};

void stop_if_out_of_range(Plant& plant, const Controller& controller, double t, const Pressures& command) {
  for (std::size_t i = 0; i < 4; ++i) {
    if (std::isfinite(command[i]) && command[i] >= 0.0 && command[i] <= plant.max_pressure_kpa()) continue;
    plant.command_pressures_kpa({0.0, 0.0, 0.0, 0.0});
    throw ControllerFault(
        fmt::format("controller '{}' asked for {} kPa on the {} at t = {:.3f} s, outside the "
                    "regulators' 0-{} kPa: vented and stopped",
                    controller.name(), command[i], kMuscleNames[i], t, plant.max_pressure_kpa()));
  }
}

}  // namespace

long run_tracking(Plant& plant, Controller& controller, const Trajectory& trajectory, const TrackingOptions& options,
                  const std::function<void(const TrackingSample&)>& on_tick) {
  if (!(options.unreachable_tolerance_deg >= 0.0) || !(options.unreachable_dwell_s >= 0.0)) {
    throw std::invalid_argument("tracking: unreachable tolerance and dwell must be >= 0");
  }
  const double period = controller.period_s();
  const double max_kpa = plant.max_pressure_kpa();
  const double start = plant.time_s();
  const long ticks = static_cast<long>(std::ceil(trajectory.duration_s() / period - 1e-9));
  controller.reset();
  std::array<ReachWatch, 2> watch = {ReachWatch(options.unreachable_tolerance_deg, options.unreachable_dwell_s),
                                     ReachWatch(options.unreachable_tolerance_deg, options.unreachable_dwell_s)};
  WristAngles zero{};
  bool zeroed = !options.zero_at_start;
  for (long k = 0; k < ticks; ++k) {
    const double t = static_cast<double>(k) * period;
    TrackingSample sample{.t_s = t, .desired = trajectory.reference_at(t), .reading = plant.read_angles()};
    if (!zeroed && sample.reading.valid) {
      zero = sample.reading.angles;
      zeroed = true;
    }
    sample.reading.valid = sample.reading.valid && zeroed;
    sample.reading.angles.fe_deg -= zero.fe_deg;
    sample.reading.angles.ur_deg -= zero.ur_deg;
    sample.reading.time_s -= start;
    sample.command = controller.command(t, sample.desired, sample.reading);
    if (options.out_of_range == TrackingOptions::OutOfRange::kStop)
      stop_if_out_of_range(plant, controller, t, sample.command);
    for (std::size_t i = 0; i < 4; ++i) {
      const double p = options.active_axes[i / 2] ? sample.command[i] : 0.0;
      sample.command[i] = std::isfinite(p) ? std::clamp(p, 0.0, max_kpa) : 0.0;
    }
    const AxisFlags said = controller.unreachable();
    const double errors[2] = {sample.desired.angles.fe_deg - sample.reading.angles.fe_deg,
                              sample.desired.angles.ur_deg - sample.reading.angles.ur_deg};
    for (std::size_t a = 0; a < 2; ++a) {
      const bool stuck = sample.reading.valid &&
                         watch[a].update(t, errors[a], sample.command[2 * a], sample.command[2 * a + 1], max_kpa);
      sample.unreachable[a] = options.active_axes[a] && (said[a] || stuck);
    }
    plant.command_pressures_kpa(sample.command);
    if (on_tick) on_tick(sample);
    plant.wait_until(start + t + period);
  }
  plant.command_pressures_kpa({0.0, 0.0, 0.0, 0.0});
  return ticks;
}

}  // namespace softwrist::control
