#include "independent_device/regulator.h"

#include <algorithm>
#include <cmath>

namespace softwrist::independent {

void Regulator::reset(double kpa) {
  rc_ = y_ = x_ = kpa;
  v_ = 0.0;
  delay_.clear();
}

double Regulator::pwm(double command_kpa) const {
  const double c = std::clamp(command_kpa, 0.0, spec_.max_kpa);
  if (spec_.pwm_levels <= 0) return c;
  return std::round(c / spec_.max_kpa * spec_.pwm_levels) * spec_.max_kpa / spec_.pwm_levels;
}

bool Regulator::steady(double u) const {
  constexpr double kTol = 1e-12;
  return std::abs(rc_ - u) < kTol && std::abs(y_ - u) < kTol && std::abs(x_ - u) < kTol && std::abs(v_) < kTol;
}

void Regulator::step(double command_kpa, double dt_s) {
  const double u = pwm(command_kpa);
  if (steady(u)) {  // nothing moves: skip the sub-steps (the rigs hold pressures for long)
    time_ += dt_s;
    if (spec_.dead_time_s > 0.0) {
      delay_.clear();
      delay_.emplace_back(time_, u);
    }
    return;
  }
  double h_max = 5e-4;
  if (spec_.second_order_wn_rad_s > 0.0) h_max = std::min(h_max, 0.3 / spec_.second_order_wn_rad_s);
  const int n = std::max(1, static_cast<int>(std::ceil(dt_s / h_max - 1e-9)));
  const double h = dt_s / n;
  if (h != cached_h_) {
    cached_h_ = h;
    alpha_rc_ = 1.0 - std::exp(-h / spec_.rc_tau_s);
    alpha_fill_ = 1.0 - std::exp(-h / (spec_.tau_s + spec_.fill_tau_extra_s));
    alpha_vent_ = 1.0 - std::exp(-h / (spec_.tau_s + spec_.vent_tau_extra_s));
  }
  for (int i = 0; i < n; ++i) substep(u, h);
}

void Regulator::substep(double u, double h) {
  time_ += h;
  rc_ += (u - rc_) * alpha_rc_;
  double target = rc_;
  if (spec_.dead_time_s > 0.0) {
    delay_.emplace_back(time_, rc_);
    while (delay_.size() >= 2 && delay_[1].first <= time_ - spec_.dead_time_s) delay_.pop_front();
    target = delay_.front().second;
  }
  double dy = (target - y_) * (target > y_ ? alpha_fill_ : alpha_vent_);
  if (spec_.rate_limit_kpa_per_s > 0.0) {
    const double limit = spec_.rate_limit_kpa_per_s * h;
    dy = std::clamp(dy, -limit, limit);
  }
  y_ = std::clamp(y_ + dy, 0.0, spec_.max_kpa);
  if (spec_.second_order_wn_rad_s > 0.0) {
    const double wn = spec_.second_order_wn_rad_s;
    v_ += h * (wn * wn * (y_ - x_) - 2.0 * spec_.second_order_zeta * wn * v_);
    x_ += h * v_;
  } else {
    x_ = y_;
    v_ = 0.0;
  }
}

double Regulator::transducer_kpa() const { return std::max(0.0, x_); }

double Regulator::line_kpa(double session_s) const {
  const double drift = spec_.gain_drift * (1.0 - std::exp(-session_s / spec_.gain_drift_tau_s));
  return transducer_kpa() / (1.0 + drift);
}

double Regulator::muscle_kpa(double session_s) const {
  const double line = line_kpa(session_s);
  const double a = spec_.leak_coefficient_sqrt_kpa;
  if (a <= 0.0) return line;
  const double root = 0.5 * (-a + std::sqrt(a * a + 4.0 * line));  // P_m + a sqrt(P_m) = P_line
  return root * root;
}

double Regulator::monitor_kpa() const { return transducer_kpa() * spec_.monitor_gain + spec_.monitor_offset_kpa; }

}  // namespace softwrist::independent
