#include "sim/simulated_plant.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "physics/units.h"

namespace softwrist::sim {

control::WristAngles wrist_angles_from_hand_axis(const double v[3]) {
  // Ry(fe) Rz(-ur) e_x = (cos ur cos fe, -sin ur, -cos ur sin fe).
  return {.fe_deg = units::rad_to_deg(std::atan2(-v[2], v[0])),
          .ur_deg = units::rad_to_deg(std::asin(std::clamp(-v[1], -1.0, 1.0)))};
}

SimulatedPlant::SimulatedPlant(const Model& model, double max_pressure_kpa, ImuModel imu)
    : wrist_(model), max_pressure_kpa_(max_pressure_kpa), imu_(imu), rng_(imu.seed) {
  if (!(imu_.period_s > 0.0) || imu_.noise_std_deg < 0.0 || imu_.bias_limit_deg < 0.0) {
    throw std::invalid_argument("IMU model: needs period > 0, noise and bias limit >= 0");
  }
  std::uniform_real_distribution<double> bias(-imu_.bias_limit_deg, imu_.bias_limit_deg);
  bias_ = {.fe_deg = bias(rng_), .ur_deg = bias(rng_)};
  forearm_body_ = model.id(mjOBJ_BODY, "forearm");
  hand_body_ = model.id(mjOBJ_BODY, "hand");
  sample();
}

void SimulatedPlant::command_pressures_kpa(const control::Pressures& pressures) {
  for (std::size_t i = 0; i < 4; ++i) {
    if (!(pressures[i] >= 0.0 && pressures[i] <= max_pressure_kpa_)) {  // NaN fails too
      wrist_.command_pressures_kpa({0.0, 0.0, 0.0, 0.0});
      throw control::PlantFault(fmt::format("a command of {} kPa for the {} is outside 0-{} kPa: vented", pressures[i],
                                            control::kMuscleNames[i], max_pressure_kpa_));
    }
  }
  wrist_.command_pressures_kpa(pressures);
}

control::WristAngles SimulatedPlant::true_angles() const {
  return {.fe_deg = units::rad_to_deg(wrist_.angle(physics::WristAxis::kFlexionExtension)),
          .ur_deg = units::rad_to_deg(wrist_.angle(physics::WristAxis::kUlnarRadial))};
}

control::WristAngles SimulatedPlant::ideal_imu_angles() {
  // The hand's x axis in the forearm frame: R_forearm^T (R_hand e_x); xmat is row-major.
  const mjData* d = wrist_.data();
  const double* forearm = d->xmat + 9 * forearm_body_;
  const double* hand = d->xmat + 9 * hand_body_;
  const double hand_x[3] = {hand[0], hand[3], hand[6]};
  double v[3];
  for (int i = 0; i < 3; ++i) v[i] = forearm[i] * hand_x[0] + forearm[3 + i] * hand_x[1] + forearm[6 + i] * hand_x[2];
  return wrist_angles_from_hand_axis(v);
}

void SimulatedPlant::sample() {
  const control::WristAngles exact = ideal_imu_angles();
  std::normal_distribution<double> noise(0.0, imu_.noise_std_deg);
  reading_ = {.angles = {.fe_deg = exact.fe_deg + bias_.fe_deg + (imu_.noise_std_deg > 0 ? noise(rng_) : 0.0),
                         .ur_deg = exact.ur_deg + bias_.ur_deg + (imu_.noise_std_deg > 0 ? noise(rng_) : 0.0)},
              .time_s = wrist_.time(),
              .valid = true};
  next_sample_ = wrist_.time() + imu_.period_s;
}

void SimulatedPlant::wait_until(double t) {
  const double dt = wrist_.model()->opt.timestep;
  while (wrist_.time() < t - 0.5 * dt) {
    if (held_) {
      wrist_.run_held(dt, units::deg_to_rad(held_->fe_deg), units::deg_to_rad(held_->ur_deg));
    } else {
      wrist_.run(dt);
    }
    if (wrist_.time() >= next_sample_ - 0.5 * dt) sample();
  }
}

}  // namespace softwrist::sim
