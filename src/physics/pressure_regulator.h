#pragma once
// The pressure regulator's response to its command. The paper gives no regulator dynamics (sim/device.h says which
// values are assumed). By default a first-order lag, tau dp/dt = u - p, with another tau while the pressure falls
// (venting through the exhaust is weaker than filling from the supply). Real proportional regulators close a pressure
// loop around a valve whose spool or pilot has its own dynamics, and their step responses lag in an S and may
// overshoot: a second-order response (Richer & Hurmuzlu, J. Dyn. Syst. Meas. Control 122:416, 2000, the spool as a
// second-order system; Beater, Pneumatic Drives, 2007, ch. 5). softwrist's form adds a second time tau2 to the lag,
//   tau2^2 d2p/dt2 + tau dp/dt + p = u,
// i.e. natural frequency 1/tau2 and damping ratio tau / (2 tau2): at tau2 = 0 it is the first-order lag exactly, a
// small tau2 delays the start of the rise, tau2 > tau/2 overshoots. Pressures in any one unit (the plugin's kPa).

namespace softwrist::physics {

struct RegulatorResponse {
  double time_constant = 0.1;       // tau [s]
  double vent_time_constant = 0.0;  // [s]: tau while the pressure falls (the command below it); 0: time_constant
  double second_order_time = 0.0;   // tau2 [s]; below kMinSecondOrderTime, first order

  // Below a tenth of a millisecond the second pole lies beyond 10 kHz: first order for every step softwrist takes.
  static constexpr double kMinSecondOrderTime = 1e-4;
  bool second_order() const { return second_order_time >= kMinSecondOrderTime; }
  // tau for a pressure `error` = command - pressure below (venting) or above zero.
  double time_constant_towards(double error) const;
};

// First order: dp/dt towards the command.
double pressure_rate(const RegulatorResponse& response, double commanded, double pressure);

struct RegulatedPressure {
  double pressure = 0.0;
  double rate = 0.0;  // dp/dt
};

// Second order: the state `dt` [s] later with the command held, exactly (the matrix exponential of the linear
// system), so that an explicit step of any length stays stable however fast the second pole; the venting time
// constant where the command lies below the pressure. With !second_order(), the first-order lag's exact step and its
// rate at the new pressure.
RegulatedPressure regulator_step(const RegulatorResponse& response, RegulatedPressure state, double commanded,
                                 double dt);

}  // namespace softwrist::physics
