// The localisation's tests (diagnosis/localization.h): under the null (the model right, residuals pure noise) the
// group test's p-values are uniform, so alpha is the false-alarm rate it claims; a systematic residual gives small
// ones; the chi-squared tail matches its closed form.

#include "diagnosis/localization.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>

namespace softwrist::diagnosis {
namespace {

// A trial of `groups` repeat groups of `repeats` measurements, its noise estimated from the pooled within-group
// variance (as prepare() does for repeated measurements), and the residuals: noise plus `offset` in every group.
struct NoisyTrial {
  PreparedTrial trial;
  std::vector<double> residuals;
  std::vector<std::size_t> members;
};

NoisyTrial noisy_trial(std::mt19937_64& rng, int groups, int repeats, double sigma, double offset) {
  std::normal_distribution<double> noise(0.0, sigma);
  NoisyTrial t;
  t.trial.name = "trial";
  t.trial.unit = "N m";
  double within = 0.0;
  for (int g = 0; g < groups; ++g) {
    std::vector<double> r;
    double mean = 0.0;
    for (int k = 0; k < repeats; ++k) {
      r.push_back(offset + noise(rng));
      mean += r.back() / repeats;
    }
    for (double v : r) {
      within += (v - mean) * (v - mean);
      t.trial.points.push_back(Point{.measured = v, .group = g, .unit = g});
      t.residuals.push_back(v);
    }
  }
  t.trial.noise_dof = groups * (repeats - 1);
  t.trial.noise = std::sqrt(within / t.trial.noise_dof);
  t.members.resize(t.residuals.size());
  for (std::size_t i = 0; i < t.members.size(); ++i) t.members[i] = i;
  return t;
}

TEST(Localization, GroupTestPValuesAreUniformUnderTheNull) {
  std::mt19937_64 rng(11);
  constexpr int kTrials = 4000;
  std::vector<double> p;
  for (int i = 0; i < kTrials; ++i) {
    const NoisyTrial t = noisy_trial(rng, 8, 3, 0.05, 0.0);
    p.push_back(group_test(t.trial, t.residuals, t.members).p_value);
  }
  std::sort(p.begin(), p.end());
  double ks = 0.0;  // Kolmogorov-Smirnov distance to U(0, 1)
  for (int i = 0; i < kTrials; ++i) {
    ks = std::max(
        {ks, std::abs(p[i] - static_cast<double>(i) / kTrials), std::abs(p[i] - static_cast<double>(i + 1) / kTrials)});
  }
  EXPECT_LT(ks, 1.63 / std::sqrt(kTrials)) << "KS critical value at the 1 % level";
  // The false alarms at alpha = 0.01 and 0.05, within 4 binomial standard deviations of their rate.
  for (const double alpha : {0.01, 0.05}) {
    const double rate = static_cast<double>(std::lower_bound(p.begin(), p.end(), alpha) - p.begin()) / kTrials;
    EXPECT_NEAR(rate, alpha, 4.0 * std::sqrt(alpha * (1.0 - alpha) / kTrials)) << alpha;
  }
}

TEST(Localization, GroupTestFindsASystematicResidualOfTwoNoiseUnits) {
  std::mt19937_64 rng(12);
  int found = 0;
  for (int i = 0; i < 200; ++i) {
    const NoisyTrial t = noisy_trial(rng, 8, 3, 0.05, 0.1);  // every group off by two standard deviations
    const LocalizationEntry e = group_test(t.trial, t.residuals, t.members);
    found += e.p_value < 0.01 ? 1 : 0;
    EXPECT_NEAR(e.residual, 0.1, 0.05);
  }
  // F(8, 16) with a noncentrality of 8 x 3 x 2^2 = 96: power 0.999 at alpha 0.01 (20 000 simulated trials).
  EXPECT_GE(found, 195);
}

// Two degrees of freedom: the upper tail of chi^2(2) is exp(-x / 2) (a periodogram bin under white noise).
TEST(Localization, ChiSquaredTailMatchesItsClosedForm) {
  for (const double x : {0.1, 1.0, 4.0, 13.8}) EXPECT_NEAR(chi_squared_p_value(x, 2.0), std::exp(-x / 2.0), 1e-12);
  // F(d1, infinity) * d1 is chi^2(d1): a very large d2 approaches it.
  EXPECT_NEAR(f_test_p_value(2.0, 2.0, 1e7), std::exp(-2.0), 1e-5);
}

// Holm's step-down procedure (Holm 1979): the k-th smallest of m p-values is compared with alpha / (m - k + 1), and
// testing stops at the first that fails. Here m = 5 and alpha = 0.05: 0.001 < 0.01, 0.011 < 0.0125 and
// 0.016 < 0.0167 reject; 0.03 > 0.025 stops, so 0.04 (< 0.05) is not reached. Bonferroni (0.01) rejects only 0.001.
TEST(Localization, HolmStepDownRejectsWhatBonferroniDoesAndTheStepsBelowTheFirstFailure) {
  const std::vector<double> p = {0.04, 0.016, 0.001, 0.03, 0.011};
  EXPECT_EQ(holm_significant(p, 0.05), (std::vector<bool>{false, true, true, false, true}));
  // Under the null its family-wise error rate stays at alpha: 20 uniform p-values per family.
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  int families_with_a_rejection = 0;
  const int families = 20000;
  for (int f = 0; f < families; ++f) {
    std::vector<double> null(20);
    for (double& v : null) v = uniform(rng);
    const std::vector<bool> s = holm_significant(null, 0.05);
    families_with_a_rejection += std::count(s.begin(), s.end(), true) > 0 ? 1 : 0;
  }
  // The rate is 1 - 0.9975^20 = 0.0488 (the first step is Bonferroni's); 4 binomial standard errors: 0.006.
  EXPECT_NEAR(static_cast<double>(families_with_a_rejection) / families, 0.0488, 0.006);
  // A NaN p rejects nothing, and an empty family nothing.
  EXPECT_EQ(holm_significant({std::nan(""), 0.001}, 0.05), (std::vector<bool>{false, true}));
  EXPECT_TRUE(holm_significant({}, 0.05).empty());
}

}  // namespace
}  // namespace softwrist::diagnosis
