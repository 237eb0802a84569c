#pragma once
// One pressure channel: Arduino PWM command -> RC low-pass of the signal conditioning -> QB3 closed-loop regulator
// -> tube -> fPAM, with the QB3's analog pressure monitor (paper Sec. "Exosuit Prototype").
//
// Nominal: 8-bit PWM (Arduino Uno analogWrite) over 0-137 kPa, RC filter tau = 10 ms (ripple of the 490 Hz PWM
// below 1 %), and a first-order fill/vent of tau = 60 ms: a QB3 responds in tens of ms dead-ended (Proportion-Air
// QB series data sheet), and filling ~0.15 L of fPAM through 1-2 m of 1/4" tubing adds a comparable time
// (flow ~100 NL/min). The regulator's own transducer closes its loop, so the monitor reports that transducer.
// regulator_lag forms: a second-order (underdamped) response; slower venting than filling (exhaust flow through
// the relief seat is subsonic and small at low gauge pressure); a slew-rate limit (choked supply flow) with a dead
// time (transport and valve dead band).
// outside:regulator_gain_drift: the internal transducer's gain drifts as the regulator warms up, so the regulator
// holds its transducer (and the monitor) at the command while the true pressure is lower.
// outside:leaking_fitting: a leaking push-to-connect fitting at the muscle: orifice flow ~ sqrt(P_m) through the
// tube's resistance gives P_line = P_m + a sqrt(P_m); the monitor (at the regulator) does not see it.

#include <deque>
#include <utility>

namespace softwrist::independent {

struct RegulatorSpec {
  double max_kpa = 137.0;
  int pwm_levels = 255;
  double rc_tau_s = 0.010;
  double tau_s = 0.060;
  // regulator_lag forms
  double fill_tau_extra_s = 0.0, vent_tau_extra_s = 0.0;
  double rate_limit_kpa_per_s = 0.0;  // 0: none
  double dead_time_s = 0.0;
  double second_order_wn_rad_s = 0.0;  // 0: none
  double second_order_zeta = 0.5;
  // outside forms
  double gain_drift = 0.0;           // transducer reads high by this fraction once warm
  double gain_drift_tau_s = 1800.0;  // warm-up time constant (30 min)
  double leak_coefficient_sqrt_kpa = 0.0;
  // device-to-device variation of the monitor (calibration)
  double monitor_gain = 1.0, monitor_offset_kpa = 0.0;
};

class Regulator {
 public:
  explicit Regulator(const RegulatorSpec& spec) : spec_(spec) {}
  void reset(double kpa);
  void step(double command_kpa, double dt_s);
  // What the regulator's transducer reads (the loop holds it at the command).
  double transducer_kpa() const;
  // True outlet pressure and pressure inside the muscle; session_s: time since the session (and warm-up) began.
  double line_kpa(double session_s) const;
  double muscle_kpa(double session_s) const;
  // The analog monitor output in kPa, before the ADC (noise and quantisation are the sensor's).
  double monitor_kpa() const;

 private:
  double pwm(double command_kpa) const;
  bool steady(double u) const;
  void substep(double u, double h);

  RegulatorSpec spec_;
  double time_ = 0.0;
  double rc_ = 0.0, y_ = 0.0, x_ = 0.0, v_ = 0.0;
  std::deque<std::pair<double, double>> delay_;
  double cached_h_ = -1.0, alpha_rc_ = 0.0, alpha_fill_ = 0.0, alpha_vent_ = 0.0;
};

}  // namespace softwrist::independent
