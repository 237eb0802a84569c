#include "independent_device/controller.h"

#include <algorithm>
#include <cmath>

namespace softwrist::independent {

void PaperController::reset(bool fe_active, bool ur_active) {
  command_kpa = {fe_active ? initial_kpa : 0.0, fe_active ? initial_kpa : 0.0, ur_active ? initial_kpa : 0.0,
                 ur_active ? initial_kpa : 0.0};
}

void PaperController::update(double desired_fe_deg, double desired_ur_deg, double measured_fe_deg,
                             double measured_ur_deg, bool fe_active, bool ur_active) {
  // positive: index of the muscle moving the axis in the positive direction (flexor 0, ulnar 2).
  auto axis = [&](double error_deg, std::size_t positive) {
    const std::size_t agonist = error_deg >= 0.0 ? positive : positive + 1;
    const std::size_t antagonist = error_deg >= 0.0 ? positive + 1 : positive;
    const double delta = gain_kpa_per_deg * std::abs(error_deg);
    command_kpa[agonist] = std::clamp(command_kpa[agonist] + delta, 0.0, max_kpa);
    const double factor = command_kpa[antagonist] > threshold_kpa ? 2.0 : 1.0;
    command_kpa[antagonist] = std::clamp(command_kpa[antagonist] - factor * delta, 0.0, max_kpa);
  };
  if (fe_active) axis(desired_fe_deg - measured_fe_deg, 0);
  if (ur_active) axis(desired_ur_deg - measured_ur_deg, 2);
}

}  // namespace softwrist::independent
