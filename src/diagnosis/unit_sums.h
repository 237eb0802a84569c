#pragma once
// A model's held-out residuals summed per split unit (gap_problem.h): what a bootstrap resamples. Internal to
// src/diagnosis.

#include <utility>
#include <vector>

namespace softwrist::diagnosis {

// Per trial and split unit: sum of (r/sigma)^2 and count, over held-out measurements.
struct UnitSums {
  std::vector<std::vector<std::pair<double, int>>> per_trial;  // [trial][unit]
};

}  // namespace softwrist::diagnosis
