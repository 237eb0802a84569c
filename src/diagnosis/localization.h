#pragma once
// Where the residual lies: for each trial, the measurements split by what might carry a gap (held angle, pressure,
// muscle, regime, direction of motion, frequency band), each part's systematic residual beside what the
// repeat-to-repeat noise alone would give, and a test of whether it is larger.
//
// The test: within a part, the repeat groups' mean residuals r_g (n_g measurements each) would be noise alone if
// the model were right, so F = sum n_g r_g^2 / (G sigma^2) follows an F(G, dof_sigma) distribution (sigma the
// trial's noise with its degrees of freedom). A frequency band of a trajectory's residual uses the periodogram:
// 2 sum |X_k|^2 / (N sigma^2) follows chi^2 with two degrees of freedom per frequency under white noise. Parts are
// significant below alpha divided by the number of parts tested (Bonferroni).

#include <string>
#include <vector>

#include "diagnosis/replay.h"

namespace softwrist::diagnosis {

struct LocalizationEntry {
  std::string experiment;  // the trial
  std::string where;       // "all", "angle -45 deg (wrapping)", "pressure 68 kPa", "flexion/extension 0.1-1 Hz", ...
  double residual = 0.0;   // RMS of the systematic residual (group means, or the band's amplitude), trial unit
  double noise = 0.0;      // what noise alone would give for it
  double p_value = 1.0;
  bool significant = false;
  std::string unit;
  int count = 0;  // measurements in the part
  // For the residual map: the part's centre (NaN where it has none).
  double angle_deg = NAN, pressure_kpa = NAN;
};

// p of an F(d1, d2) statistic and of a chi^2(k) statistic (upper tails).
double f_test_p_value(double f, double d1, double d2);
double chi_squared_p_value(double x, double k);

// Which of `p_values` are significant at family-wise error rate `alpha`, by Holm's step-down procedure (Holm 1979,
// "A simple sequentially rejective multiple test procedure", Scand. J. Statist. 6): the k-th smallest is compared with
// alpha / (m - k + 1), and testing stops at the first that fails. It controls the family-wise rate as Bonferroni does
// and rejects at least what Bonferroni rejects; a NaN p rejects nothing.
std::vector<bool> holm_significant(const std::vector<double>& p_values, double alpha);

// The parts of every trial, most significant (largest residual over noise) first. `residuals[t]` are trial t's
// measured minus predicted values, aligned with its points.
std::vector<LocalizationEntry> localize(const std::vector<PreparedTrial>& trials,
                                        const std::vector<std::vector<double>>& residuals,
                                        const sim::DeviceDescription& nominal, double alpha);

// One part's group test (the "all" entry of a trial is the whole-trial gap test).
LocalizationEntry group_test(const PreparedTrial& trial, const std::vector<double>& residuals,
                             const std::vector<std::size_t>& members);

}  // namespace softwrist::diagnosis
