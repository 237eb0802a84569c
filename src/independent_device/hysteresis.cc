#include "independent_device/hysteresis.h"

#include <algorithm>
#include <cmath>

namespace softwrist::independent {
namespace {

// Maxwell-slip elements: slip lengths relative to law.length_m and force weights (sum 1), spread over a decade
// and a half as in the identified PAM models (Vo-Minh et al. 2011 use 4-10 elements).
constexpr std::array<double, kSlipElements> kWidths{0.125, 0.25, 0.5, 1.0, 2.0, 4.0};
constexpr std::array<double, kSlipElements> kWeights{0.10, 0.15, 0.20, 0.20, 0.20, 0.15};

}  // namespace

double hysteresis_force_n(const HysteresisLaw& law, const HysteresisState& state, double area_force_n) {
  if (law.kind == HysteresisKind::none) return 0.0;
  const double level = law.constant_n + law.pressure_fraction * area_force_n;
  if (law.kind == HysteresisKind::dahl) return level * state.z;
  double sum = 0.0;
  for (std::size_t i = 0; i < kSlipElements; ++i) sum += kWeights[i] * state.slip[i];
  return level * sum;
}

void hysteresis_advance(const HysteresisLaw& law, HysteresisState& state, double lengthening_m) {
  if (law.kind == HysteresisKind::none || lengthening_m == 0.0) return;
  if (law.kind == HysteresisKind::dahl) {
    const double decay = std::exp(-std::abs(lengthening_m) / law.length_m);
    state.z = lengthening_m > 0.0 ? 1.0 - (1.0 - state.z) * decay : -1.0 + (1.0 + state.z) * decay;
    return;
  }
  for (std::size_t i = 0; i < kSlipElements; ++i)
    state.slip[i] = std::clamp(state.slip[i] + lengthening_m / (law.length_m * kWidths[i]), -1.0, 1.0);
}

}  // namespace softwrist::independent
