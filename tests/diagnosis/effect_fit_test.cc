// Ranking the effects fitted in one round (diagnosis/effect_fit.h, leader_of_round): the one-standard-error rule
// (Breiman, Friedman, Olshen & Stone 1984, Sec. 3.4.3; Hastie, Tibshirani & Friedman 2009, Sec. 7.10). A richer
// effect leads when the held-out data tell its error from a simpler one's; when they do not, the simpler leads.
// Among what the held-out data cannot separate, the training part decides where it tells the fits apart. Held-out
// (and training) sums are made directly: 40 units of 25 measurements of unit noise, each unit with a systematic
// residual that varies from unit to unit (as a model's error does from held angle to held angle).

#include "diagnosis/effect_fit.h"

#include <cmath>
#include <functional>
#include <random>
#include <vector>

#include <gtest/gtest.h>

namespace softwrist::diagnosis {
namespace {

constexpr int kUnits = 40, kPerUnit = 25;
constexpr EffectId kOne = EffectId::kMountStretch, kFour = EffectId::kHysteresis;  // base forms of 1 and 4 parameters

class LeaderOfRound : public ::testing::Test {
 protected:
  LeaderOfRound() {
    for (int u = 0; u < kUnits; ++u) {
      for (int i = 0; i < kPerUnit; ++i) {
        sweep_.points.push_back(Point{.unit = u, .heldout = true});
        sweep_.points.push_back(Point{.unit = u, .heldout = false});
      }
    }
    trials_.push_back(sweep_);
  }

  // Held-out sums of a model whose systematic residual in unit u is `mean` + `spread` * pattern(u), on the
  // measurements' noise drawn from one seed (models compared on the same data share it).
  UnitSums sums(double mean, double spread, const std::function<double(int)>& pattern) {
    std::normal_distribution<double> normal(0.0, 1.0);
    std::mt19937_64 noise(7);
    UnitSums s;
    s.per_trial.emplace_back(kUnits);
    for (int u = 0; u < kUnits; ++u) {
      const double systematic = mean + spread * pattern(u);
      auto& unit = s.per_trial[0][static_cast<std::size_t>(u)];
      for (int i = 0; i < kPerUnit; ++i) unit.first += std::pow(systematic + normal(noise), 2);
      unit.second = kPerUnit;
    }
    return s;
  }
  UnitSums sums(double mean, double spread) {
    std::normal_distribution<double> normal(0.0, 1.0);
    return sums(mean, spread, [&](int) { return normal(rng_); });
  }

  // A fit of effect `id` in its base form (the rule counts its parameters: fitted_parameters): the mounts' one
  // stiffness, the hysteresis's four.
  EffectFit fit(const char* name, EffectId id, UnitSums s, UnitSums training = {}) {
    EffectFit f{.id = id, .name = name, .values = std::vector<double>(effect_spec(id).parameters.size(), 0.0)};
    f.heldout_error_after = problem_.heldout_error(s);
    f.heldout_after_sums = std::move(s);
    set_training(f, training.per_trial.empty() ? sums(0.5, 0.0) : std::move(training));  // default: every fit alike
    return f;
  }
  // `f`'s training sums and the training gap they give.
  void set_training(EffectFit& f, UnitSums training) {
    f.training_gap_after = problem_.training_gap(training);
    f.training_after_sums = std::move(training);
  }

  std::mt19937_64 rng_{7};
  Trial trial_{.kind = TrialKind::kTorqueSweep, .name = "sweep", .file = "sweep.csv"};
  PreparedTrial sweep_{.trial = &trial_, .name = "sweep", .unit = "N m", .noise = 1.0};
  std::vector<PreparedTrial> trials_;
  ReplayEngine engine_{sim::PluginSet::Default()};
  GapProblem problem_{trials_, engine_};
  DiagnosisOptions options_;
};

TEST_F(LeaderOfRound, ARicherEffectTheDataPreferLeads) {
  std::vector<EffectFit> fits = {fit("simple", kOne, sums(1.0, 0.3)), fit("rich", kFour, sums(0.3, 0.3))};
  ASSERT_LT(fits[1].heldout_error_after, fits[0].heldout_error_after);
  EXPECT_EQ(leader_of_round(problem_, fits, options_, 1), 1u);
  EXPECT_FALSE(fits[0].within_one_se_of_best) << fits[0].se_of_difference_to_best;
  EXPECT_TRUE(fits[1].within_one_se_of_best);
}

TEST_F(LeaderOfRound, WhatTheDataCannotSeparateGoesToTheSimplerEffect) {
  // The same data and the same mean square error; where each model errs differs from unit to unit by 0.3.
  const auto pairs = [](int u) { return (u / 2) % 2 ? -1.0 : 1.0; };
  const auto alternate = [](int u) { return u % 2 ? -1.0 : 1.0; };
  std::vector<EffectFit> fits = {fit("rich", kFour, sums(0.8, 0.3, pairs)),
                                 fit("simple", kOne, sums(0.8, 0.3, alternate)),
                                 fit("inapplicable", kOne, sums(0.0, 0.0))};
  fits[2].applicable = false;  // never the leader
  const std::size_t best = fits[0].heldout_error_after < fits[1].heldout_error_after ? 0 : 1;
  const std::size_t other = 1 - best;
  EXPECT_EQ(leader_of_round(problem_, fits, options_, 1), 1u);
  const double difference = fits[other].heldout_error_after - fits[best].heldout_error_after;
  EXPECT_TRUE(fits[other].within_one_se_of_best)
      << "difference " << difference << ", se " << fits[other].se_of_difference_to_best;
  EXPECT_GT(fits[other].se_of_difference_to_best, 2.0 * difference);
  // Without the rule the lower error leads, whatever its parameters.
  options_.one_se_rule = false;
  EXPECT_EQ(leader_of_round(problem_, fits, options_, 1), best);
}

// What the held-out part cannot separate, the training part can: the richer effect fits it with a systematic residual
// of 0.4 noise units where the simpler leaves 1.5, far beyond two paired standard errors, and leads. Where the training
// part does not separate them either (0.8 and 0.85, patterns of their own), the simpler leads as before; and so with
// the training part's say turned off.
TEST_F(LeaderOfRound, TheTrainingPartBreaksATieTheHeldOutPartLeaves) {
  const auto pairs = [](int u) { return (u / 2) % 2 ? -1.0 : 1.0; };
  const auto alternate = [](int u) { return u % 2 ? -1.0 : 1.0; };
  std::vector<EffectFit> fits = {fit("rich", kFour, sums(0.8, 0.3, pairs), sums(0.4, 0.3, alternate)),
                                 fit("simple", kOne, sums(0.8, 0.3, alternate), sums(1.5, 0.3, pairs))};
  EXPECT_EQ(leader_of_round(problem_, fits, options_, 1), 0u);
  EXPECT_TRUE(fits[0].within_one_se_of_best && fits[1].within_one_se_of_best);
  set_training(fits[0], sums(0.8, 0.3, alternate));
  set_training(fits[1], sums(0.85, 0.3, pairs));
  EXPECT_EQ(leader_of_round(problem_, fits, options_, 1), 1u);
  set_training(fits[1], sums(1.5, 0.3, pairs));
  options_.training_separation_se = 0.0;
  EXPECT_EQ(leader_of_round(problem_, fits, options_, 1), 1u);
}

// A fit from the nominal within its tolerances carries the tolerance fit's parameters (EffectFit::base_parameters):
// between what the data cannot separate, a fit from the nominal as placed leads, however few parameters the other
// effect has of its own.
TEST_F(LeaderOfRound, TheBasesParametersCountInTheRule) {
  const auto pairs = [](int u) { return (u / 2) % 2 ? -1.0 : 1.0; };
  const auto alternate = [](int u) { return u % 2 ? -1.0 : 1.0; };
  std::vector<EffectFit> fits = {fit("as placed", kFour, sums(0.8, 0.3, pairs)),
                                 fit("within the tolerances", kOne, sums(0.8, 0.3, alternate))};
  EXPECT_EQ(leader_of_round(problem_, fits, options_, 1), 1u);  // as the test above: the one-parameter effect
  fits[1].base_parameters = 31;
  EXPECT_EQ(leader_of_round(problem_, fits, options_, 1), 0u);
}

// The rule counts the parameters a fit moved: an extension only where it was kept (EffectFit::extended). Unextended,
// the mounts' fit is one stiffness and leads a four-parameter hysteresis the data cannot tell from it, though its
// held-out error is a little higher; with its three extensions kept it has four too, and the lower error leads.
// (Counting every slot, the mounts had four either way.)
TEST_F(LeaderOfRound, AnExtensionCountsOnlyWhereItWasKept) {
  const auto pairs = [](int u) { return (u / 2) % 2 ? -1.0 : 1.0; };
  const auto alternate = [](int u) { return u % 2 ? -1.0 : 1.0; };
  std::vector<EffectFit> fits = {fit("hysteresis", kFour, sums(0.8, 0.3, pairs)),
                                 fit("mounts", kOne, sums(0.82, 0.3, alternate))};
  ASSERT_GT(fits[1].heldout_error_after, fits[0].heldout_error_after);
  EXPECT_EQ(leader_of_round(problem_, fits, options_, 1), 1u);
  EXPECT_TRUE(fits[1].within_one_se_of_best) << fits[1].se_of_difference_to_best;
  fits[1].extended = true;
  EXPECT_EQ(leader_of_round(problem_, fits, options_, 1), 0u);
}

// The single fits' leader starts the combination on its own base, so it is one that may join it (cuts the held-out
// error by min_gain with its interval above zero): a simpler fit the data cannot tell from the best does not lead when
// it cuts nothing. Where none may join, the round's leader as before.
TEST_F(LeaderOfRound, TheSingleFitsLeaderIsOneThatJoinsTheCombination) {
  const auto pairs = [](int u) { return (u / 2) % 2 ? -1.0 : 1.0; };
  const auto alternate = [](int u) { return u % 2 ? -1.0 : 1.0; };
  std::vector<EffectFit> fits = {fit("rich", kFour, sums(0.8, 0.3, pairs)),
                                 fit("simple", kOne, sums(0.8, 0.3, alternate))};
  ASSERT_EQ(leader_of_round(problem_, fits, options_, 1), 1u);              // the simpler, as above
  EXPECT_EQ(leader_of_single_fits(problem_, fits, options_, 1, true), 1u);  // neither cuts anything
  fits[0].shrink_fraction = 0.6;
  fits[0].ci_low = 0.2;
  EXPECT_TRUE(joins_combination(fits[0], true, options_));
  EXPECT_FALSE(joins_combination(fits[1], true, options_));
  EXPECT_EQ(leader_of_single_fits(problem_, fits, options_, 1, true), 0u);
  fits[0].ci_low = -0.1;  // its interval reaches zero: it joins only where the interval says nothing
  EXPECT_EQ(leader_of_single_fits(problem_, fits, options_, 1, true), 1u);
  EXPECT_EQ(leader_of_single_fits(problem_, fits, options_, 1, false), 0u);
}

TEST_F(LeaderOfRound, NoneApplicableIsNoLeader) {
  std::vector<EffectFit> fits = {fit("a", kOne, sums(0.5, 0.1))};
  fits[0].applicable = false;
  EXPECT_EQ(leader_of_round(problem_, fits, options_, 1), fits.size());
}

// The bootstrap interval of a shrink (gap_problem.h, bootstrap_interval) of a change that moves some held-out units
// only: a torque sweep holding out four angles of which the muscle wraps at two, a wrap that closes those two and
// leaves the straight-line two bit for bit. One resample in sixteen draws the straight-line angles alone and closes
// exactly 0; such resamples say nothing of the wrap, and the interval is the shrink's among those that hold a moved
// unit. The same two units made worse give an interval below zero: the rule still refuses a change that hurts.
TEST(BootstrapInterval, ResamplesHoldingNoUnitTheChangeMovesSayNothing) {
  Trial trial{.kind = TrialKind::kTorqueSweep, .name = "sweep", .file = "sweep.csv"};
  PreparedTrial sweep{.trial = &trial, .name = "sweep", .unit = "N m", .noise = 1.0};
  for (int u = 0; u < 4; ++u) sweep.points.push_back(Point{.unit = u, .heldout = true});
  std::vector<PreparedTrial> trials = {sweep};
  ReplayEngine engine{sim::PluginSet::Default()};
  const GapProblem problem{trials, engine};
  const auto sums = [](std::vector<double> mean_square) {
    UnitSums s;
    for (double m : mean_square) s.per_trial.resize(1), s.per_trial[0].emplace_back(25.0 * m, 25);
    return s;
  };
  const UnitSums before = sums({10.0, 10.0, 5.0, 5.0});
  const auto [low, high] = bootstrap_interval(problem, before, sums({1.0, 1.0, 5.0, 5.0}), 2000, 3);
  EXPECT_GT(low, 0.0) << "interval " << low << " to " << high;
  const auto [worse_low, worse_high] = bootstrap_interval(problem, before, sums({20.0, 20.0, 5.0, 5.0}), 2000, 3);
  EXPECT_LT(worse_high, 0.0) << "interval " << worse_low << " to " << worse_high;
  // One moved unit alone is not conditioned on (every resample would hold it): a quarter of the resamples leave it out
  // and close 0.
  const auto [one_low, one_high] = bootstrap_interval(problem, before, sums({1.0, 10.0, 5.0, 5.0}), 2000, 3);
  EXPECT_EQ(one_low, 0.0) << "interval " << one_low << " to " << one_high;
  // A change that moves every unit: the moved-unit condition leaves every resample in.
  const auto [all_low, all_high] = bootstrap_interval(problem, before, sums({1.0, 1.0, 4.0, 4.0}), 2000, 3);
  EXPECT_GT(all_low, 0.0) << "interval " << all_low << " to " << all_high;
}

// The training gap is taken over every trial, the held-out error over the scored ones: a model that leaves a trial the
// tolerances explain (not scored) 3 noise units off answers for it on the training part (GapProblem::training_gap).
TEST(TrainingGap, CountsEveryTrialWhateverIsScored) {
  Trial trial{.kind = TrialKind::kTorqueSweep, .name = "sweep", .file = "sweep.csv"};
  PreparedTrial sweep{.trial = &trial, .name = "sweep", .unit = "N m", .noise = 1.0};
  sweep.points = {Point{.unit = 0, .heldout = false}, Point{.unit = 1, .heldout = true}};
  std::vector<PreparedTrial> trials = {sweep, sweep};
  ReplayEngine engine{sim::PluginSet::Default()};
  GapProblem problem{trials, engine};
  const Predictions predictions = {{1.0, 0.0}, {3.0, 3.0}};  // measured 0: the first trial 1 and 0 off, the second 3
  problem.set_scored({true, false});
  EXPECT_DOUBLE_EQ(problem.heldout_error(problem.heldout_sums(predictions)), 0.0);
  // sqrt(max(0, 1 - 1)) = 0 and sqrt(9 - 1), averaged over the two trials of the one kind.
  EXPECT_DOUBLE_EQ(problem.training_gap(problem.training_sums(predictions)), 0.5 * std::sqrt(8.0));
}

}  // namespace
}  // namespace softwrist::diagnosis
