#include "control/tracking_metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

namespace softwrist::control {
namespace {

std::vector<double> moving_average(std::span<const double> t, std::span<const double> y, double width_s) {
  std::vector<double> out(y.size());
  std::size_t lo = 0, hi = 0;
  double sum = 0.0;
  for (std::size_t i = 0; i < y.size(); ++i) {
    while (hi < y.size() && t[hi] <= t[i] + 0.5 * width_s) sum += y[hi++];
    while (t[lo] < t[i] - 0.5 * width_s) sum -= y[lo++];
    out[i] = sum / static_cast<double>(hi - lo);
  }
  return out;
}

}  // namespace

StepResponse step_response(std::span<const double> t_s, std::span<const double> angle_deg, double from_deg,
                           double to_deg, const StepResponseOptions& options) {
  if (t_s.empty() || t_s.size() != angle_deg.size()) {
    throw std::invalid_argument("step response: needs as many angles as times, at least one");
  }
  if (from_deg == to_deg) throw std::invalid_argument("step response: the step has no size");
  const std::vector<double> y = moving_average(t_s, angle_deg, options.smoothing_s);
  const double size = to_deg - from_deg;
  const double sign = size > 0.0 ? 1.0 : -1.0;
  // Progress along the step: 0 at `from`, 1 at `to`.
  const auto progress = [&](std::size_t i) { return (y[i] - from_deg) / size; };
  StepResponse r;
  double t10 = std::numeric_limits<double>::quiet_NaN(), t90 = t10;
  double peak = 0.0;
  for (std::size_t i = 0; i < y.size(); ++i) {
    if (std::isnan(t10) && progress(i) >= 0.1) t10 = t_s[i];
    if (std::isnan(t90) && progress(i) >= 0.9) t90 = t_s[i];
    peak = std::max(peak, sign * (y[i] - to_deg));
  }
  r.rise_time_s = t90 - t10;
  r.overshoot_pct = 100.0 * peak / std::abs(size);
  double sum = 0.0;
  int n = 0;
  for (std::size_t i = 0; i < y.size(); ++i) {
    if (t_s[i] >= t_s.back() - options.final_window_s) {
      sum += angle_deg[i] - to_deg;
      ++n;
    }
  }
  r.final_error_deg = sum / n;
  return r;
}

double rms_error(std::span<const double> desired, std::span<const double> actual) {
  if (desired.size() != actual.size()) throw std::invalid_argument("rms error: sizes differ");
  if (desired.empty()) return std::numeric_limits<double>::quiet_NaN();
  double sum = 0.0;
  for (std::size_t i = 0; i < desired.size(); ++i) sum += (actual[i] - desired[i]) * (actual[i] - desired[i]);
  return std::sqrt(sum / static_cast<double>(desired.size()));
}

}  // namespace softwrist::control
