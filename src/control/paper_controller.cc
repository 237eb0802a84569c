#include "control/paper_controller.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace softwrist::control {
namespace {

// One axis: `positive` moves the wrist towards positive angles (flexor, ulnar muscle), `negative` the other way.
void update_pair(double error_deg, const PaperControllerParameters& p, double& positive, double& negative) {
  const double change = p.gain_kpa_per_deg * std::abs(error_deg);
  double& agonist = error_deg >= 0.0 ? positive : negative;
  double& antagonist = error_deg >= 0.0 ? negative : positive;
  agonist += change;
  antagonist -= antagonist > p.initial_kpa ? p.release_factor * change : change;
  agonist = std::clamp(agonist, 0.0, p.max_kpa);
  antagonist = std::clamp(antagonist, 0.0, p.max_kpa);
}

}  // namespace

PaperController::PaperController(PaperControllerParameters parameters) : parameters_(parameters) {
  const auto& p = parameters_;
  if (!(p.period_s > 0.0) || !(p.gain_kpa_per_deg >= 0.0) || !(p.max_kpa > 0.0) || !(p.initial_kpa >= 0.0) ||
      p.initial_kpa > p.max_kpa || !(p.release_factor >= 1.0)) {
    throw std::invalid_argument("paper controller: needs period > 0, gain >= 0, 0 <= initial <= max, release >= 1");
  }
  reset();
}

void PaperController::reset() { pressures_.fill(parameters_.initial_kpa); }

Pressures PaperController::command(double, const Reference& desired, const ImuReading& reading) {
  return reading.valid ? update(desired.angles, reading.angles) : pressures_;
}

const Pressures& PaperController::update(const WristAngles& desired, const WristAngles& measured) {
  const double fe_error = desired.fe_deg - measured.fe_deg;
  const double ur_error = desired.ur_deg - measured.ur_deg;
  if (!std::isfinite(fe_error) || !std::isfinite(ur_error)) return pressures_;  // hold on a bad reading
  update_pair(fe_error, parameters_, pressures_[0], pressures_[1]);
  update_pair(ur_error, parameters_, pressures_[2], pressures_[3]);
  return pressures_;
}

}  // namespace softwrist::control
