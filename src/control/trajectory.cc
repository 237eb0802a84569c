#include "control/trajectory.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace softwrist::control {

StepTrajectory::StepTrajectory(std::vector<WristAngles> levels, double hold_s)
    : levels_(std::move(levels)), hold_s_(hold_s) {
  if (levels_.empty()) throw std::invalid_argument("step trajectory: needs at least one level");
  for (const WristAngles& level : levels_) {
    if (!std::isfinite(level.fe_deg) || !std::isfinite(level.ur_deg)) {
      throw std::invalid_argument("step trajectory: levels must be finite");
    }
  }
  if (!(hold_s_ > 0.0) || !std::isfinite(hold_s_)) throw std::invalid_argument("step trajectory: hold_s must be > 0");
}

WristAngles StepTrajectory::at(double t_s) const {
  const double index = std::floor(std::max(t_s, 0.0) / hold_s_);
  return levels_[static_cast<std::size_t>(std::min(index, static_cast<double>(levels_.size() - 1)))];
}

SinusoidTrajectory::SinusoidTrajectory(SinusoidParameters parameters) : parameters_(parameters) {
  const auto& p = parameters_;
  for (double v : {p.fe_min_deg, p.fe_max_deg, p.ur_min_deg, p.ur_max_deg, p.phase_lag_deg}) {
    if (!std::isfinite(v)) throw std::invalid_argument("sinusoid trajectory: limits and phase must be finite");
  }
  if (p.fe_min_deg > p.fe_max_deg || p.ur_min_deg > p.ur_max_deg) {
    throw std::invalid_argument("sinusoid trajectory: each axis needs min <= max");
  }
  if (!(p.period_s > 0.0) || !(p.periods > 0.0) || !std::isfinite(p.period_s) || !std::isfinite(p.periods)) {
    throw std::invalid_argument("sinusoid trajectory: period_s and periods must be > 0");
  }
}

WristAngles SinusoidTrajectory::at(double t_s) const {
  const auto& p = parameters_;
  const double phase = 2.0 * std::numbers::pi * t_s / p.period_s;
  const double lag = p.phase_lag_deg * std::numbers::pi / 180.0;
  return {.fe_deg = 0.5 * (p.fe_max_deg + p.fe_min_deg) + 0.5 * (p.fe_max_deg - p.fe_min_deg) * std::sin(phase),
          .ur_deg = 0.5 * (p.ur_max_deg + p.ur_min_deg) + 0.5 * (p.ur_max_deg - p.ur_min_deg) * std::sin(phase - lag)};
}

WristAngles SinusoidTrajectory::rate_at(double t_s) const {
  const auto& p = parameters_;
  const double omega = 2.0 * std::numbers::pi / p.period_s;
  const double lag = p.phase_lag_deg * std::numbers::pi / 180.0;
  return {.fe_deg = 0.5 * (p.fe_max_deg - p.fe_min_deg) * omega * std::cos(omega * t_s),
          .ur_deg = 0.5 * (p.ur_max_deg - p.ur_min_deg) * omega * std::cos(omega * t_s - lag)};
}

}  // namespace softwrist::control
