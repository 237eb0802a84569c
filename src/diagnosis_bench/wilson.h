#pragma once
// Wilson's score interval for a rate of k successes in n cases (Wilson 1927): unlike k/n +- 1.96 sqrt(p(1-p)/n) it
// stays inside [0, 1] and is not zero-width at 0 or n successes, which is what a benchmark of a few dozen cases
// per rate needs.

#include <algorithm>
#include <cmath>
#include <utility>

namespace softwrist::diagnosis_bench {

// The 95 % interval (z = 1.96); [0, 1] for no cases.
inline std::pair<double, double> wilson_interval(int successes, int cases, double z = 1.96) {
  if (cases <= 0) return {0.0, 1.0};
  const double n = cases, p = successes / n, z2 = z * z;
  const double centre = (p + z2 / (2 * n)) / (1 + z2 / n);
  const double half = z * std::sqrt(p * (1 - p) / n + z2 / (4 * n * n)) / (1 + z2 / n);
  return {std::max(0.0, centre - half), std::min(1.0, centre + half)};
}

}  // namespace softwrist::diagnosis_bench
