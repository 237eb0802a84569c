#include "independent_device/sensors.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

#include "independent_device/units.h"

namespace softwrist::independent {

ImuPair::ImuPair(const ImuSpec& spec, std::uint64_t seed, std::uint64_t trial, bool noisy)
    : spec_(spec), noisy_(noisy), noise_(seed, "imu-noise", trial), jitter_(seed, "imu-jitter", trial) {
  for (std::size_t i = 0; i < 2; ++i) {
    ar_[i] = spec_.noise_sd_deg * noise_.normal();  // stationary start
    rate_[i] = spec_.drift_rate_sd_deg_per_s * noise_.normal();
  }
}

void ImuPair::observe(double t_s, double fe_rad, double ur_rad) {
  history_.push_back({t_s, fe_rad, ur_rad});
  while (history_.size() > 2 && history_.front()[0] < t_s - 0.5) history_.pop_front();
}

std::array<double, 2> ImuPair::truth_at(double t_s) const {
  if (history_.empty()) return {0.0, 0.0};
  if (t_s <= history_.front()[0]) return {history_.front()[1], history_.front()[2]};
  if (t_s >= history_.back()[0]) return {history_.back()[1], history_.back()[2]};
  const auto it = std::lower_bound(history_.begin(), history_.end(), t_s,
                                   [](const std::array<double, 3>& h, double t) { return h[0] < t; });
  const auto& b = *it;
  const auto& a = *(it - 1);
  const double f = (t_s - a[0]) / (b[0] - a[0]);
  return {a[1] + f * (b[1] - a[1]), a[2] + f * (b[2] - a[2])};
}

void ImuPair::sample(double t_s) {
  double query = t_s;
  if (spec_.latency_s > 0.0 || spec_.latency_jitter_s > 0.0)
    query -= spec_.latency_s + spec_.latency_jitter_s * (2.0 * jitter_.uniform() - 1.0);
  const auto truth = truth_at(query);
  // Hand axis in the anatomical forearm frame (x distal, y palmar, z radial): R = Rz(fe) Ry(ur) applied to x.
  const Eigen::Vector3d hand(std::cos(truth[1]) * std::cos(truth[0]), std::cos(truth[1]) * std::sin(truth[0]),
                             -std::sin(truth[1]));
  // Seen from a forearm IMU rolled by gamma about the forearm's axis.
  const Eigen::Vector3d seen =
      Eigen::AngleAxisd(spec_.roll_misalignment_rad, Eigen::Vector3d::UnitX()).inverse() * hand;
  std::array<double, 2> angle_deg{to_deg(std::atan2(seen.y(), seen.x())),
                                  to_deg(std::asin(std::clamp(-seen.z(), -1.0, 1.0)))};
  if (noisy_) {
    const double dt = sampled_ ? std::max(0.0, t_s - last_sample_s_) : 0.0;
    const double rho = std::exp(-dt / spec_.noise_correlation_s);
    for (std::size_t i = 0; i < 2; ++i) {
      ar_[i] = rho * ar_[i] + std::sqrt(1.0 - rho * rho) * spec_.noise_sd_deg * noise_.normal();
      drift_[i] += rate_[i] * dt + spec_.random_walk_deg_per_sqrt_s * std::sqrt(dt) * noise_.normal();
      angle_deg[i] = quantise(angle_deg[i] + ar_[i] + drift_[i], 1.0 / spec_.resolution_deg);
    }
  }
  raw_ = angle_deg;
  last_sample_s_ = t_s;
  sampled_ = true;
}

void ImuPair::zero() { offset_ = raw_; }

double read_pressure_monitor_kpa(double monitor_kpa, Rng* rng) {
  if (rng == nullptr) return std::max(0.0, monitor_kpa);
  return std::max(0.0, quantise(monitor_kpa + 0.15 * rng->normal(), 10.0));
}

double read_torque_sensor_nm(double torque_nm, Rng* rng) {
  if (rng == nullptr) return torque_nm;
  return quantise(torque_nm + 0.006 * rng->normal(), 1000.0);
}

double read_tensile_load_cell_n(double force_n, Rng* rng) {
  if (rng == nullptr) return force_n;
  return quantise(force_n + 0.3 * rng->normal(), 10.0);
}

}  // namespace softwrist::independent
