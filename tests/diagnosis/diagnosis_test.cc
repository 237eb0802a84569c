// The gap diagnosis on data from a simulated exosuit (diagnosis/synthetic_device.h) with one effect switched on at a
// known magnitude: its own fit recovers it, the whole catalogue names it, the localisation puts a local effect where
// it acts, the paper's case (Section Torque applied by the exosuit: stretching withheld, MAE 1.111 -> 0.283 N m)
// comes out as mount_stretch, and bad files are reported one by one while the rest is diagnosed.

#include "diagnosis/diagnosis.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <iostream>
#include <map>
#include <set>
#include <span>
#include <string>

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "diagnosis/benchmark.h"
#include "diagnosis/csv_import.h"
#include "diagnosis/effect_fit.h"
#include "diagnosis/gap_problem.h"
#include "diagnosis/parameter_intervals.h"
#include "diagnosis/synthetic_device.h"
#include "diagnosis/tolerance_fit.h"
#include "io/csv.h"
#include "physics/fpam_force.h"
#include "physics/fpam_hysteresis.h"
#include "physics/units.h"
#include "sim/device.h"
#include "support/end_to_end_test.h"
#include "support/scratch_dir_test.h"

namespace softwrist::diagnosis {
namespace {

namespace fs = std::filesystem;

sim::DeviceDescription paper_device() {
  return sim::load_device(fs::path(SOFTWRIST_SOURCE_DIR) / "models/paper_device.json");
}

class DiagnosisTest : public testing::ScratchDirTest {
 protected:
  // Synthesizes "real" data from `real` and diagnoses it against `nominal`, with the given effects (all if empty).
  Diagnosis run(const SyntheticDevice& real, const sim::DeviceDescription& nominal, std::vector<EffectId> effects = {},
                SyntheticPlan plan = {.trajectory_s = 12.0}) {
    write_synthetic_data(real, plan, dir_ / "real");
    return diagnose(load_real_data(dir_ / "real"), nominal, engine_, {.effects = std::move(effects), .bootstrap = 100});
  }
  const EffectFit& fit_of(const Diagnosis& d, EffectId id) {
    for (const auto& f : d.effects) {
      if (f.id == id) return f;
    }
    throw std::logic_error("effect not fitted");
  }
  double param(const EffectFit& f, const std::string& name) {
    for (const auto& [n, v] : f.params) {
      if (n == name) return v;
    }
    throw std::logic_error("no parameter " + name);
  }
  ReplayEngine engine_{sim::PluginSet::Default()};
};

TEST_F(DiagnosisTest, NoEffectGivesNone) {
  const Diagnosis d = run({.device = paper_device()}, paper_device());
  EXPECT_EQ(d.verdict, "none") << d.reason;
  for (const auto& t : d.trials) EXPECT_FALSE(t.significant) << t.experiment << " p = " << t.p_value;
  EXPECT_EQ(d.routing, sim::Routing::kSpatial);
}

// A device whose muscles act on their own axes alone (the paper's torque model, as the independent device has them)
// is no effect: the diagnosis replays it with the routing that fits (DiagnosisOptions::routing), and the spatial
// model's coupling between the axes is not read as one.
TEST_F(DiagnosisTest, MusclesActingOnTheirOwnAxesAreRoutedPlanarNotAnEffect) {
  SOFTWRIST_SKIP_END_TO_END_UNDER_SANITIZERS();
  sim::DeviceDescription planar = paper_device();
  planar.routing = sim::Routing::kPlanar;
  const Diagnosis d = run({.device = planar}, paper_device(), {EffectId::kRegulatorLag, EffectId::kMountStretch});
  EXPECT_EQ(d.routing, sim::Routing::kPlanar);
  ASSERT_EQ(d.routing_training_error.size(), 2u);
  EXPECT_EQ(d.routing_training_error[1].first, sim::Routing::kPlanar);
  EXPECT_LT(d.routing_training_error[1].second, 0.5 * d.routing_training_error[0].second);
  EXPECT_EQ(d.verdict, "none") << d.reason;
  // Routed as the files say, the same data show the coupling as a gap.
  write_synthetic_data({.device = planar}, {.trajectory_s = 12.0}, dir_ / "real");
  const Diagnosis fixed =
      diagnose(load_real_data(dir_ / "real"), paper_device(), engine_,
               {.effects = {EffectId::kRegulatorLag}, .routing = sim::Routing::kSpatial, .bootstrap = 100});
  EXPECT_EQ(fixed.routing, sim::Routing::kSpatial);
  EXPECT_TRUE(fixed.routing_training_error.empty());
  EXPECT_NE(fixed.verdict, "none") << fixed.reason;
}

// The paper's withheld stretching (Table torque_measurement_parameters) on a device whose muscles act on their own
// axes: named, with the series stiffness, and the parameters' intervals (a calibration's) replay the data routed as
// the diagnosis chose, the placement files being spatial.
TEST_F(DiagnosisTest, WithheldStretchingOnAPlanarDeviceKeepsItsRoutingInTheIntervals) {
  SOFTWRIST_SKIP_END_TO_END_UNDER_SANITIZERS();
  sim::DeviceDescription planar = paper_device();
  planar.routing = sim::Routing::kPlanar;
  sim::DeviceDescription rigid = paper_device();
  rigid.stretch_mode = physics::StretchMode::kNone;
  const Diagnosis d = run({.device = planar}, rigid, {EffectId::kMountStretch, EffectId::kRegulatorLag});
  ASSERT_EQ(d.verdict, "mount_stretch") << d.reason;
  EXPECT_EQ(d.routing, sim::Routing::kPlanar);
  EXPECT_NEAR(param(d.combination.front(), "K_series_n_per_cm2"), 30.16, 1.5);
  const std::vector<ParameterInterval> intervals = combination_intervals(d, rigid, engine_);
  bool found = false;
  for (const ParameterInterval& p : intervals) {
    if (p.name != "K_series_n_per_cm2") continue;
    found = true;
    // Replayed spatial (the files' routing), the same fit spread 4.3-216 N/cm^2.
    EXPECT_LE(p.low, p.value);
    EXPECT_GE(p.high, p.value);
    EXPECT_NEAR(p.low, 30.16, 1.5);
    EXPECT_NEAR(p.high, 30.16, 1.5);
  }
  EXPECT_TRUE(found);
}

// Table torque_measurement_parameters: the device's mounts stretch (K1 = -43.36, K2 = -1097.50 N/cm^2); the nominal
// model leaves stretching out, as the paper's first torque model did.
TEST_F(DiagnosisTest, PaperCaseWithheldStretchingIsMountStretch) {
  SOFTWRIST_SKIP_END_TO_END_UNDER_SANITIZERS();
  sim::DeviceDescription nominal = paper_device();
  nominal.stretch_mode = physics::StretchMode::kNone;
  const Diagnosis d = run({.device = paper_device()}, nominal);
  ASSERT_EQ(d.verdict, "mount_stretch") << d.reason;
  // The series stiffness of K1 and K2: 1/(1/sqrt(43.36) + 1/sqrt(1097.5))^2 = 30.16 N/cm^2, within 5 %.
  EXPECT_NEAR(param(d.combination.front(), "K_series_n_per_cm2"), 30.16, 1.5);
  // The torque MAE falls at least as much as the paper's 1.111 -> 0.283 N m (a factor 3.9).
  EXPECT_GT(torque_mae(d, false) / torque_mae(d, true), 1.111 / 0.283)
      << "MAE before " << torque_mae(d, false) << ", after " << torque_mae(d, true);
  // Decided again without fitting (redecide: what diagnose-bench's calibration of the settings weighs): with the same
  // settings the same verdict; asking the leader alone to close more of the gap than it does, not this one.
  const DiagnosisOptions same{.bootstrap = 100};
  Diagnosis again = d;
  redecide(again, same);
  EXPECT_EQ(again.verdict, d.verdict);
  EXPECT_EQ(again.reason, d.reason);
  DiagnosisOptions stricter = same;
  stricter.explained_fraction = d.explained_fraction + 0.05;
  stricter.pair_share = 1.0;
  redecide(again, stricter);
  EXPECT_NE(again.verdict, "mount_stretch") << again.reason;
}

// A gap no catalogue effect closes is an effect outside the catalogue (`unexplained`) only where it is evidence of
// one: a gap trial left at least contradiction_gap noise units off within the tolerances; below, it is the model's
// own inexactness and the verdict is `none` (the independent device's nominal, seeds 9 and 10: a tensile test 1.0-1.3
// noise units off over 1689 points).
TEST(DiagnosisVerdict, AGapNoEffectExplainsIsUnexplainedOnlyWhereItEvidencesAnEffect) {
  using ::testing::HasSubstr;
  Diagnosis d;
  d.tolerance.params = {{"fpam_params.r0_scale", 1.01}};
  d.trials.push_back({.experiment = "tensile/trials",
                      .kind = TrialKind::kTensile,
                      .excess_nominal = 7.3,
                      .excess_within_tolerance = 1.3,
                      .p_value = 1e-9,
                      .significant = true,
                      .gap = true});
  redecide(d, DiagnosisOptions{});
  EXPECT_EQ(d.verdict, "none");
  EXPECT_THAT(d.reason, HasSubstr("the largest gap left within the tolerances, 1.30 noise units (tensile/trials)"));
  EXPECT_THAT(d.reason, HasSubstr("no catalogue effect reduces the held-out error meaningfully"));
  d.trials.front().excess_within_tolerance = 2.4;  // below the default 3 (unexplained while it was 1.5)
  redecide(d, DiagnosisOptions{});
  EXPECT_EQ(d.verdict, "none") << d.reason;
  d.trials.front().excess_within_tolerance = 3.4;
  redecide(d, DiagnosisOptions{});
  EXPECT_EQ(d.verdict, "unexplained") << d.reason;
  DiagnosisOptions lower;
  lower.contradiction_gap = 1.0;
  d.trials.front().excess_within_tolerance = 1.3;
  redecide(d, lower);
  EXPECT_EQ(d.verdict, "unexplained") << d.reason;
}

// A named effect contradicts a trial the nominal matched only where the model it was added to matched it too: a miss
// that base already had is the tolerance fit's trade between trials (the independent device's seed 12: a regulator
// added to a tolerance fit that had moved the ellipses' angles from 0.0-0.6 to 2.8-3.9 noise units).
TEST(DiagnosisVerdict, AnEffectIsContradictedOnlyByATrialItsBaseMatched) {
  using ::testing::HasSubstr;
  Diagnosis d;
  d.tolerance.params = {{"regulator_lag.time_constant_s", 0.07}};
  d.tolerance.moved = {0.4};
  EffectFit lag{.id = EffectId::kRegulatorLag, .name = "regulator_lag", .within_tolerances = true};
  d.effects = d.combination = {lag};
  d.leading_effect = "regulator_lag";
  d.explained_fraction = 0.78;
  d.trials.push_back({.experiment = "ellipse pressures",
                      .kind = TrialKind::kTrajectory,
                      .excess_nominal = 2.5,
                      .excess_corrected = 0.6,
                      .excess_within_tolerance = 2.2,
                      .p_value = 1e-9,
                      .significant = true,
                      .gap = true});
  d.trials.push_back({.experiment = "ellipse angles",
                      .kind = TrialKind::kTrajectory,
                      .excess_nominal = 0.4,
                      .excess_corrected = 3.95,
                      .excess_within_tolerance = 3.95,
                      .p_value = 0.5,
                      .remaining_significant = true});
  redecide(d, DiagnosisOptions{});
  EXPECT_EQ(d.verdict, "regulator_lag") << d.reason;
  // The same miss by an effect fitted from the nominal as placed, which matched the trial: contradicted.
  d.effects.front().within_tolerances = false;
  redecide(d, DiagnosisOptions{});
  EXPECT_EQ(d.verdict, "unexplained");
  EXPECT_THAT(d.reason,
              HasSubstr("regulator_lag contradicts ellipse angles: the nominal matched it (0.40 noise units)"));
  // And by one fitted on a base that matched it too.
  d.effects.front().within_tolerances = true;
  d.trials.back().excess_within_tolerance = 0.5;
  redecide(d, DiagnosisOptions{});
  EXPECT_EQ(d.verdict, "unexplained") << d.reason;
}

// Where the leading single fit falls short fitted with the tolerances too, a runner-up fitted with them is named when
// it fits the training part better than the leader so and closes explained_fraction of the held-out gap; the pair
// rule does not hide it behind the leader. The figures are the independent device's seed 16, elliptical_section: the
// mounts led the single fits (26 %; jointly 24 %, training error 30.1), the wrap jointly 76 % (1.37).
TEST(DiagnosisVerdict, ARunnerUpFittedWithTheTolerancesIsNamedWhereItFitsTheTrainingPartBetter) {
  using ::testing::HasSubstr;
  Diagnosis d;
  d.tolerance.params = {{"torque_rig.flexor.w2_cm", 3.7}};
  d.tolerance.moved = {1.0};
  const EffectFit mounts{.id = EffectId::kMountStretch, .name = "mount_stretch"};
  const EffectFit hysteresis{.id = EffectId::kHysteresis, .name = "hysteresis"};
  d.effects = {mounts, hysteresis};
  d.combination = {mounts, hysteresis};
  d.leading_effect = "mount_stretch";
  d.explained_fraction = 0.26;
  d.gap_nominal = 6.7;
  d.gap_corrected = 3.0;  // the pair closes 55 %, the leader 26 %: the pair rule alone would name the mounts
  d.trials.push_back({.experiment = "torque_sweep/trials",
                      .kind = TrialKind::kTorqueSweep,
                      .excess_nominal = 13.2,
                      .excess_within_tolerance = 11.6,
                      .p_value = 1e-30,
                      .significant = true,
                      .gap = true});
  d.leader_beyond_tolerance = Diagnosis::BeyondTolerance{
      .effect = "mount_stretch", .train_error_with_effect = 30.1, .explained_fraction = 0.24};
  d.runners_up_beyond_tolerance.push_back({.id = EffectId::kWrapGeometry,
                                           .effect = "wrap_geometry",
                                           .train_error_with_effect = 1.37,
                                           .explained_fraction = 0.76,
                                           .explained_in_acted_on = 0.76});
  redecide(d, DiagnosisOptions{});
  EXPECT_EQ(d.verdict, "wrap_geometry") << d.reason;
  EXPECT_THAT(d.reason, HasSubstr("the leading single fit, mount_stretch, explains 24 % so"));
  EXPECT_TRUE(d.also_effects.empty());
  // Fitting the training part no better than the leader, it is not preferred on its held-out share: the pair rule.
  d.runners_up_beyond_tolerance.front().train_error_with_effect = 30.1;
  redecide(d, DiagnosisOptions{});
  EXPECT_EQ(d.verdict, "mount_stretch") << d.reason;
  EXPECT_EQ(d.also_effects, std::vector<std::string>{"hysteresis"});
  // Fitting better but closing less than explained_fraction: not named either; without the pair, unexplained.
  d.runners_up_beyond_tolerance.front().train_error_with_effect = 1.37;
  d.runners_up_beyond_tolerance.front().explained_in_acted_on = 0.35;
  d.combination = {mounts};
  redecide(d, DiagnosisOptions{});
  EXPECT_EQ(d.verdict, "unexplained") << d.reason;
}

// The nominal within its tolerances explains every trial, but only with a tolerance pinned at an edge of its box that
// an effect owning it, fitted alone, takes beyond that edge while closing pair_share of its base's held-out error where
// it acts (EffectFit::shrink_where_acting): that effect is named. The figures are the independent device's seed 43
// (development data, dev_pinned_tolerance.json): strap_stiffening, whose tolerances closed the sweep's 19.65 noise
// units to 0.60 with the mounts' series stiffness at its lower edge (21.12 N/cm^2 of 21.12-39.22) and the mount stretch
// alone at 13.0 closed 69 %; the nominal, whose regulator's time constant sat at its upper edge (0.072 s) while the
// regulator alone, at 0.036 s, closed 1 %.
TEST(DiagnosisVerdict, ATolerancePinnedAtItsEdgeThatItsEffectTakesFurtherNamesTheEffect) {
  using ::testing::HasSubstr;
  Diagnosis d;
  d.tolerance.params = {{"mount_stretch.K_series_n_per_cm2", 21.12}, {"regulator_lag.time_constant_s", 0.072}};
  d.tolerance.moved = {-1.0, 1.0};
  d.tolerance.boxes = {{21.12, 39.22}, {0.048, 0.072}};
  d.tolerance.at_bound = {"mount_stretch.K_series_n_per_cm2", "regulator_lag.time_constant_s"};
  const EffectFit lag{.id = EffectId::kRegulatorLag,
                      .name = "regulator_lag",
                      .params = {{"time_constant_s", 0.036}},
                      .shrink_where_acting = 0.01};
  const EffectFit mounts{.id = EffectId::kMountStretch,
                         .name = "mount_stretch",
                         .params = {{"K1_n_per_cm2", 18.7}, {"K_series_n_per_cm2", 13.0}},
                         .shrink_where_acting = 0.69};
  d.effects = {mounts, lag};
  d.combination = {mounts};
  d.trials.push_back({.experiment = "torque_sweep/trials",
                      .kind = TrialKind::kTorqueSweep,
                      .excess_nominal = 19.65,
                      .excess_within_tolerance = 0.60,
                      .p_value = 1e-30,
                      .significant = true});
  const auto verdict = [&] {
    redecide(d, DiagnosisOptions{});
    return d.verdict;
  };
  EXPECT_EQ(verdict(), "mount_stretch") << d.reason;
  EXPECT_THAT(d.reason, HasSubstr("at an edge of a tolerance, mount_stretch.K_series_n_per_cm2=21.12, which "
                                  "mount_stretch fitted alone takes further (13)"));
  // Fitted alone within the box, or past the fitted value but not past the edge: the tolerances explain the trials.
  d.effects.front().params.back().second = 24.3;
  EXPECT_EQ(verdict(), "none") << d.reason;
  d.tolerance.params.front().second = 21.4;  // within 2 % of the box's width: at the edge
  d.effects.front().params.back().second = 21.3;
  EXPECT_EQ(verdict(), "none") << d.reason;
  d.tolerance.params.front().second = 21.12;
  d.effects.front().params.back().second = 13.0;
  // Closing less than pair_share (0.2): the relaxed wrist on the nominals of seeds 41 and 42 closed 0 and 5 %.
  d.effects.front().shrink_where_acting = 0.15;
  EXPECT_EQ(verdict(), "none") << d.reason;
  // Not the combination's leader, closing pair_share or more: named all the same (calibration seed 1005's stiffening
  // strap, which the fPAM led with 75 %, the mounts alone past the edge at 12.6 N/cm^2 closing 36 %).
  d.effects.front().shrink_where_acting = 0.36;
  d.combination = {lag};
  EXPECT_EQ(verdict(), "mount_stretch") << d.reason;
  d.combination = {mounts};
  d.effects.front().shrink_where_acting = 0.69;
  // Fitted with its extensions, whose exponent or preload change what the series stiffness means: the base form's fit
  // they replaced is read (seed 56's sliding glove), and without one, none.
  d.effects.front().extended = true;
  EXPECT_EQ(verdict(), "none") << d.reason;
  d.effects.front().base_form =
      EffectFit::BaseForm{.params = {{"K_series_n_per_cm2", 24.3}}, .shrink_where_acting = 0.5};
  EXPECT_EQ(verdict(), "none") << d.reason;  // the base form within the box
  d.effects.front().base_form->params.front().second = 14.0;
  EXPECT_EQ(verdict(), "mount_stretch") << d.reason;
  EXPECT_THAT(d.reason, HasSubstr("mount_stretch fitted alone in its base form takes further (14) while closing 50 %"));
  d.effects.front().base_form->shrink_where_acting = 0.15;  // the base form closing less than pair_share
  EXPECT_EQ(verdict(), "none") << d.reason;
  d.effects.front().extended = false;
  d.effects.front().base_form.reset();
  // Not at an edge.
  d.tolerance.at_bound = {"regulator_lag.time_constant_s"};
  EXPECT_EQ(verdict(), "none") << d.reason;
  // A pinned regulator: named only where its fit alone takes the time constant past the upper edge (and closes
  // pair_share).
  d.effects.back().shrink_where_acting = 0.55;
  EXPECT_EQ(verdict(), "none") << d.reason;  // 0.036 s: the other way
  d.effects.back().params.front().second = 0.09;
  EXPECT_EQ(verdict(), "regulator_lag") << d.reason;
  // Both pinned and beyond: the one closing more.
  d.tolerance.at_bound = {"mount_stretch.K_series_n_per_cm2", "regulator_lag.time_constant_s"};
  EXPECT_EQ(verdict(), "mount_stretch") << d.reason;
}

// The nominal's tolerance fit with the mounts' series stiffness alone, pinned at its box's lower edge (21.12 of
// 21.12-39.22 N/cm^2, 30 % below the nominal), as on the independent device's seeds 50 and 54.
void pin_series_stiffness_at_lower_edge(ToleranceFit& fit) {
  fit.params = {{"mount_stretch.K_series_n_per_cm2", 21.12}};
  fit.moved = {-1.0};
  fit.boxes = {{21.12, 39.22}};
  fit.at_bound = {"mount_stretch.K_series_n_per_cm2"};
}

// Where the verdict names the combination's leader but the tolerances absorbed another member by spending its box
// whole, the larger is the one whose single fit closes more of its own base's held-out error. The figures are the
// independent device's seed 54 (glove_slide+second_order_response, read after its report): the regulator led and
// explained 85 % of the held-out gap, closing 28 % of its base's error; the mounts' series stiffness sat at its lower
// edge (21.12 N/cm^2), which the mounts alone took to 21.0 while closing 73 % of theirs.
TEST(DiagnosisVerdict, AnEffectTheTolerancesAbsorbedIsNamedBeforeALeaderThatClosesLessOfItsBase) {
  using ::testing::HasSubstr;
  Diagnosis d;
  pin_series_stiffness_at_lower_edge(d.tolerance);
  const EffectFit lag{.id = EffectId::kRegulatorLag,
                      .name = "regulator_lag",
                      .params = {{"time_constant_s", 0.122}},
                      .shrink_where_acting = 0.28};
  const EffectFit wrist{.id = EffectId::kPassiveWrist, .name = "passive_wrist", .shrink_where_acting = 0.27};
  const EffectFit mounts{.id = EffectId::kMountStretch,
                         .name = "mount_stretch",
                         .params = {{"K_series_n_per_cm2", 21.0}},
                         .shrink_where_acting = 0.73};
  d.effects = {lag, wrist, mounts};
  d.combination = {lag, wrist, mounts};
  d.leading_effect = "regulator_lag";
  d.explained_fraction = 0.85;
  d.gap_nominal = 1.56;
  d.gap_corrected = 0.20;
  d.trials.push_back({.experiment = "trajectory_ellipse/trials:case ellipse-1 pressures",
                      .kind = TrialKind::kTrajectory,
                      .excess_nominal = 5.0,
                      .excess_within_tolerance = 4.6,
                      .p_value = 1e-30,
                      .significant = true,
                      .gap = true});
  const auto verdict = [&] {
    redecide(d, DiagnosisOptions{});
    return d.verdict;
  };
  EXPECT_EQ(verdict(), "mount_stretch") << d.reason;
  EXPECT_EQ(d.also_effects, std::vector<std::string>{"regulator_lag"});
  EXPECT_THAT(d.reason, HasSubstr("closing 73 % of its base's held-out error where it acts, against 28 % for "
                                  "regulator_lag"));
  // Closing less of its base than the leader does of its own: the leader stays.
  d.effects.back().shrink_where_acting = 0.25;
  EXPECT_EQ(verdict(), "regulator_lag") << d.reason;
  EXPECT_TRUE(d.also_effects.empty());
  // More than the leader but less than pair_share (0.2): as little as the nominals' own pinned effects close.
  d.effects.front().shrink_where_acting = 0.10;
  d.effects.back().shrink_where_acting = 0.15;
  EXPECT_EQ(verdict(), "regulator_lag") << d.reason;
  d.effects.front().shrink_where_acting = 0.28;
  d.effects.back().shrink_where_acting = 0.73;
  // Not in the combination, so not in the corrected model: the leader stays.
  d.combination = {lag, wrist};
  EXPECT_EQ(verdict(), "regulator_lag") << d.reason;
  // A pair verdict that reported the absorbed effect as its second: the leader takes its place beside it.
  d.combination = {lag, mounts};
  d.explained_fraction = 0.3;  // below explained_fraction alone; the pair closes 87 %
  EXPECT_EQ(verdict(), "mount_stretch") << d.reason;
  EXPECT_EQ(d.also_effects, std::vector<std::string>{"regulator_lag"});
  // Within its box, or fitted with its extensions and its base form within it: no evidence the tolerances absorbed it.
  d.effects.back().params.front().second = 22.0;
  EXPECT_EQ(verdict(), "regulator_lag") << d.reason;
  EXPECT_EQ(d.also_effects, std::vector<std::string>{"mount_stretch"});
  d.effects.back().params.front().second = 21.0;
  d.effects.back().extended = true;
  d.effects.back().base_form =
      EffectFit::BaseForm{.params = {{"K_series_n_per_cm2", 22.0}}, .shrink_where_acting = 0.6};
  EXPECT_EQ(verdict(), "regulator_lag") << d.reason;
  // Its base form beyond the edge: the base form's share is weighed against the leader's.
  d.effects.back().base_form->params.front().second = 20.5;
  EXPECT_EQ(verdict(), "mount_stretch") << d.reason;
  EXPECT_THAT(d.reason, HasSubstr("fitted alone in its base form takes further (20.5) while closing 60 % of its base's "
                                  "held-out error where it acts, against 28 %"));
  d.effects.back().base_form->shrink_where_acting = 0.25;
  EXPECT_EQ(verdict(), "regulator_lag") << d.reason;
}

// An extended fit reports the base form it replaced, which the pinned-tolerance rule reads, and each fit its share
// where it acts.
TEST(DiagnosisJson, AnExtendedFitReportsTheBaseFormItReplaced) {
  Diagnosis d;
  EffectFit mounts{.id = EffectId::kMountStretch,
                   .name = "mount_stretch",
                   .params = {{"K_series_n_per_cm2", 12.96}, {"exponent", 2.05}},
                   .shrink_fraction = 0.56,
                   .extended = true,
                   .base_form = EffectFit::BaseForm{.params = {{"K_series_n_per_cm2", 13.31}},
                                                    .shrink_fraction = 0.55,
                                                    .shrink_where_acting = 0.7},
                   .shrink_where_acting = 0.71};
  d.effects = {mounts};
  const nlohmann::json j = to_json(d);
  const auto& e = j["effects"].at(0);
  EXPECT_DOUBLE_EQ(e["params"]["exponent"].get<double>(), 2.05);
  EXPECT_DOUBLE_EQ(e["shrink_where_acting"].get<double>(), 0.71);
  EXPECT_DOUBLE_EQ(e["base_form"]["params"]["K_series_n_per_cm2"].get<double>(), 13.31);
  EXPECT_DOUBLE_EQ(e["base_form"]["shrink_fraction"].get<double>(), 0.55);
  EXPECT_DOUBLE_EQ(e["base_form"]["shrink_where_acting"].get<double>(), 0.7);
  d.effects.front().extended = false;
  d.effects.front().base_form.reset();
  EXPECT_FALSE(to_json(d)["effects"].at(0).contains("base_form"));
}

// Where a small gap is left within the tolerances, below contradiction_gap, and no effect explains explained_fraction
// of it, the verdict is `none` (the model's own inexactness) unless a pinned tolerance names its effect. The figures
// are the independent device's seed 50 (its glove_slide data set, read after its report): the sweep 27.86 noise units
// off as placed, 1.77 within the tolerances with the mounts' series stiffness at its lower edge, the mounts alone,
// at 21.0 N/cm^2, closing 84 % of the error of the nominal as placed but -2 % of what the tolerances left.
TEST(DiagnosisVerdict, ASmallGapLeftWithinTheTolerancesNamesTheEffectOfAPinnedTolerance) {
  using ::testing::HasSubstr;
  Diagnosis d;
  pin_series_stiffness_at_lower_edge(d.tolerance);
  const EffectFit mounts{.id = EffectId::kMountStretch,
                         .name = "mount_stretch",
                         .params = {{"K_series_n_per_cm2", 20.99}},
                         .shrink_where_acting = 0.84};
  d.effects = {mounts};
  d.combination = {mounts};
  d.leading_effect = "mount_stretch";
  d.explained_fraction = -0.02;
  d.trials.push_back({.experiment = "torque_sweep/trials",
                      .kind = TrialKind::kTorqueSweep,
                      .excess_nominal = 27.86,
                      .excess_corrected = 1.61,
                      .excess_within_tolerance = 1.77,
                      .p_value = 1e-30,
                      .significant = true,
                      .gap = true});
  redecide(d, DiagnosisOptions{});
  EXPECT_EQ(d.verdict, "mount_stretch") << d.reason;
  EXPECT_THAT(d.reason, HasSubstr("the largest gap left within them, 1.77 noise units (torque_sweep/trials)"));
  // Within the box: the model's own inexactness.
  d.effects.front().params.front().second = 21.5;
  redecide(d, DiagnosisOptions{});
  EXPECT_EQ(d.verdict, "none") << d.reason;
  // Beyond, but the gap left evidences an effect outside the catalogue.
  d.effects.front().params.front().second = 20.99;
  d.trials.front().excess_within_tolerance = 3.5;
  redecide(d, DiagnosisOptions{});
  EXPECT_EQ(d.verdict, "unexplained") << d.reason;
}

// A gap trial as the second-effect rule reads it: significant, a gap, and what the leader's base left held out.
TrialGap gap_trial(const std::string& experiment, TrialKind kind, double excess_nominal, double p_value,
                   double heldout_excess_leader_base) {
  return {.experiment = experiment,
          .kind = kind,
          .excess_nominal = excess_nominal,
          .p_value = p_value,
          .significant = true,
          .gap = true,
          .heldout_excess_leader_base = heldout_excess_leader_base};
}

// A pair's second effect is reported beside a leader named on its own where it acts where the leader cannot: a gap
// trial the leader leaves untouched, of which the second closes at least contradiction_gap noise units. The figures are
// the independent device's seed 38 (development data): aged_fabric + exponential_limits, whose fPAM leaves the sweep
// with the relaxed wrist at 6.17 noise units (5.95 before it) and the wrist takes it to 2.04; and maxwell_slip alone,
// whose hysteresis had moved an ellipse from 4.38 to 3.59 before the relaxed wrist took it to 1.94 (its form's misfit).
TEST(DiagnosisVerdict, ASecondEffectIsReportedWhereItActsWhereTheLeaderCannot) {
  using ::testing::HasSubstr;
  Diagnosis d;
  EffectFit fabric{.id = EffectId::kFpamParams, .name = "fpam_params"};
  EffectFit wrist{.id = EffectId::kPassiveWrist, .name = "passive_wrist"};
  fabric.heldout_excess_by_trial = {6.17, 8.30};
  wrist.heldout_excess_by_trial = {2.04, 2.44};
  d.effects = d.combination = {fabric, wrist};
  d.leading_effect = "fpam_params";
  d.explained_fraction = 0.59;
  d.trials.push_back(gap_trial("torque_sweep/trials", TrialKind::kTorqueSweep, 6.0, 1e-20, 5.95));
  d.trials.push_back(gap_trial("ellipse-1", TrialKind::kTrajectory, 14.6, 1e-20, 14.61));
  redecide(d, DiagnosisOptions{});
  EXPECT_EQ(d.verdict, "fpam_params") << d.reason;
  EXPECT_EQ(d.also_effects, std::vector<std::string>{"passive_wrist"});
  EXPECT_THAT(d.reason, HasSubstr("passive_wrist acts besides: torque_sweep/trials keeps 6.17 held-out noise units"));
  // Not where the second cuts less than contradiction_gap of it.
  DiagnosisOptions stricter;
  stricter.contradiction_gap = 4.5;
  redecide(d, stricter);
  EXPECT_TRUE(d.also_effects.empty()) << d.reason;
  // Nor where the leader moved every trial the second cuts: what the second closes there is the leader's misfit.
  d.combination[0].heldout_excess_by_trial = {3.59, 8.30};
  d.combination[1].heldout_excess_by_trial = {1.94, 2.44};
  d.trials[0].heldout_excess_leader_base = 4.38;
  redecide(d, DiagnosisOptions{});
  EXPECT_EQ(d.verdict, "fpam_params") << d.reason;
  EXPECT_TRUE(d.also_effects.empty()) << d.reason;
  // Nor without the residuals per trial (a diagnosis that did not record them).
  d.combination[0].heldout_excess_by_trial.clear();
  redecide(d, DiagnosisOptions{});
  EXPECT_TRUE(d.also_effects.empty());
}

// A second effect is credited only with what it closes beyond what the tolerances, fitted to that trial alone, leave
// of it: the tolerance fit over every trial trades one trial for the others. The figures are the independent device's
// development data: `elliptical_section` of seed 41, where `passive_wrist` cut two ellipses by 3.8 and 3.7 noise units
// that the tolerances alone bring to 0.0 and 1.75; and `aged_fabric + exponential_limits` of seed 41, where the
// fabric cut the tensile test from 3.31 to 1.17 and the tolerances alone leave 3.25 (the fabric lies beyond them).
TEST(DiagnosisVerdict, ASecondEffectMustCloseWhatTheTolerancesFittedToItsTrialAloneLeave) {
  using ::testing::HasSubstr;
  Diagnosis d;
  EffectFit wrap{.id = EffectId::kWrapGeometry, .name = "wrap_geometry"};
  EffectFit wrist{.id = EffectId::kPassiveWrist, .name = "passive_wrist"};
  wrap.heldout_excess_by_trial = {4.67, 5.03};
  wrist.heldout_excess_by_trial = {0.84, 1.33};
  d.effects = d.combination = {wrap, wrist};
  d.leading_effect = "wrap_geometry";
  d.explained_fraction = 0.6;
  d.trials.push_back(gap_trial("ellipse-3", TrialKind::kTrajectory, 4.0, 1e-10, 4.80));
  d.trials.push_back(gap_trial("ellipse-4", TrialKind::kTrajectory, 4.0, 1e-10, 5.17));
  redecide(d, DiagnosisOptions{});  // not measured: the leader's residual counts whole
  EXPECT_EQ(d.also_effects, std::vector<std::string>{"passive_wrist"});
  EXPECT_THAT(d.reason, HasSubstr("ellipse-3 keeps 4.67 held-out noise units with wrap_geometry (4.80 before it)"));
  d.trials[0].heldout_excess_within_alone = 0.0;
  d.trials[1].heldout_excess_within_alone = 1.75;
  redecide(d, DiagnosisOptions{});
  EXPECT_EQ(d.verdict, "wrap_geometry") << d.reason;
  EXPECT_TRUE(d.also_effects.empty()) << d.reason;
  // Where the trial keeps its gap with the tolerances fitted to it alone, the second is reported (the second cuts it
  // by 2.14 noise units: credited at contradiction_gap 1.5, the setting when these figures were read; not at 3).
  d.combination[0].heldout_excess_by_trial = {3.31, 5.03};
  d.combination[1].heldout_excess_by_trial = {1.17, 1.33};
  d.trials[0].heldout_excess_leader_base = 3.31;
  d.trials[0].heldout_excess_within_alone = 3.25;
  redecide(d, DiagnosisOptions{});
  EXPECT_TRUE(d.also_effects.empty()) << d.reason;
  DiagnosisOptions read_at;
  read_at.contradiction_gap = 1.5;
  redecide(d, read_at);
  EXPECT_EQ(d.also_effects, std::vector<std::string>{"passive_wrist"});
  EXPECT_THAT(d.reason, HasSubstr("(3.31 before it, 3.25 with the tolerances fitted to it alone)"));
}

// Each effect, switched on with known parameters, recovered by its own fit (tolerances stated per line).
TEST_F(DiagnosisTest, EachEffectRecoveredByItsOwnFit) {
  SOFTWRIST_SKIP_END_TO_END_UNDER_SANITIZERS();
  sim::DeviceDescription device = paper_device();
  {
    SyntheticDevice real{.device = device};
    real.device.wrist.stiffness_fe *= 2.5;
    real.device.wrist.stiffness_ur *= 2.5;
    const auto d = run(real, device, {EffectId::kPassiveWrist});
    EXPECT_NEAR(param(fit_of(d, EffectId::kPassiveWrist), "stiffness_scale"), 2.5, 0.1);  // 4 %
  }
  {
    SyntheticDevice real{.device = device};
    for (auto& m : real.device.muscles) m.wrist_radius *= 0.8;
    const auto d = run(real, device, {EffectId::kWrapGeometry});
    EXPECT_NEAR(param(fit_of(d, EffectId::kWrapGeometry), "wrist_radius_scale"), 0.8, 0.01);
  }
  {
    SyntheticDevice real{.device = device};
    real.device.regulator.time_constant = 0.3;
    real.device.regulator.vent_time_constant = 0.6;  // venting twice as slowly as filling (sim::Regulator)
    const auto d = run(real, device, {EffectId::kRegulatorLag});
    EXPECT_NEAR(param(fit_of(d, EffectId::kRegulatorLag), "time_constant_s"), 0.3, 0.03);  // 10 %
    EXPECT_NEAR(param(fit_of(d, EffectId::kRegulatorLag), "vent_ratio"), 2.0, 0.2);
    // Its range of motion is not zeroed between conditions: no pressure carried into a zero to fit.
    EXPECT_EQ(param(fit_of(d, EffectId::kRegulatorLag), "rom_residual_fraction"), 0.0);
  }
  {
    SyntheticDevice real{.device = device, .imu_offset_fe_deg = 2.0, .imu_offset_ur_deg = -1.5, .imu_latency = 0.03};
    const auto d = run(real, device, {EffectId::kImuBias});
    const auto& f = fit_of(d, EffectId::kImuBias);
    EXPECT_NEAR(param(f, "offset_fe_deg"), 2.0, 0.1);
    EXPECT_NEAR(param(f, "offset_ur_deg"), -1.5, 0.1);
    EXPECT_NEAR(param(f, "latency_s"), 0.03, 0.01);  // the IMU samples every 10 ms
  }
  {
    SyntheticDevice real{.device = device, .hysteresis = 0.1};
    const auto d = run(real, device, {EffectId::kHysteresis});
    EXPECT_NEAR(param(fit_of(d, EffectId::kHysteresis), "fraction"), 0.1, 0.01);
  }
  {
    SyntheticDevice real{.device = device};
    std::vector<physics::FpamTableRow> rows = device.fpam.rows();
    for (auto& row : rows) {
      row.radius *= 0.9;
      row.max_contraction += 0.02;
    }
    real.device.fpam = physics::FpamParameters::Table(rows, device.fpam.fabric());
    write_synthetic_data(real, {.trajectory_s = 12.0}, dir_ / "real");
    // The fabric's stiffness and curvature trade off against each other and against r0 where the tensile rig's noise
    // allows (BOBYQA fitted x 0.55 and 7.8 for the true x 1 and 0); what the data fix is the force law: within 2 % of
    // the true pull, or two load-cell noises (1 N) where that is more, with the trajectory replayed from its commands.
    // Replayed from its measured pressures (the default), whose noise reaches the angles (replay.h), the fit moves
    // along that valley: the 0 kPa pull came out 1.28 N off and the 137 kPa one 1.68 N (2.5
    // %), so three load-cell noises or 2.5 % there.
    for (const PressureSource source : {PressureSource::kCommands, PressureSource::kMeasuredWhereLogged}) {
      ReplayEngine engine(sim::PluginSet::Default(), {}, source);
      auto d = diagnose(load_real_data(dir_ / "real"), device, engine,
                        {.effects = {EffectId::kFpamParams}, .bootstrap = 100});
      const auto& f = fit_of(d, EffectId::kFpamParams);
      // The search reaches the valley's floor: no more training error than the true parameters leave (BOBYQA, the
      // search before Levenberg-Marquardt, stopped at 2.5 times it on such data).
      const std::map<std::string, double> true_values{{"r0_scale", 0.9},
                                                      {"eps_max_shift", 0.02},
                                                      {"fabric_stiffness_scale", 1.0},
                                                      {"fabric_curvature", 0.0},
                                                      {"eps_max_pressure_slope", 0.0}};
      std::vector<double> true_parameters;
      for (const ParameterSpec& p : effect_spec(EffectId::kFpamParams).parameters)
        true_parameters.push_back(true_values.at(p.name));
      ModelVariant true_variant{.device = device};
      apply_effect(EffectId::kFpamParams, true_parameters, true_variant);
      const GapProblem problem(d.prepared, engine);
      EXPECT_LE(f.train_error_after, 1.01 * problem.training_error(problem.evaluate(true_variant, true)));
      EXPECT_NEAR(param(f, "r0_scale"), 0.9, 0.015);
      EXPECT_NEAR(param(f, "eps_max_shift"), 0.02, 0.003);
      const bool commands = source == PressureSource::kCommands;
      ModelVariant fitted{.device = device};
      apply_effect(EffectId::kFpamParams, f.values, fitted);
      for (const double kpa : {0.0, 34.0, 68.0, 103.0, 137.0}) {
        const double pressure = units::kpa_to_pa(kpa);
        for (double eps = 0.0; eps < 0.3; eps += 0.02) {
          const double truth = physics::fpam_force(real.device.fpam, pressure, eps);
          EXPECT_NEAR(physics::fpam_force(fitted.device.fpam, pressure, eps), truth,
                      commands ? std::max(1.0, 0.02 * truth) : std::max(1.5, 0.025 * truth))
              << kpa << " kPa, eps " << eps << (commands ? ", from the commands" : ", from the measured pressures");
        }
      }
    }
  }
}

// A device that differs from its placement file only within the placement's tolerances (Table
// tensile_testing_parameters: r0 scatters 2.6 %, eps_max 0.012 between the paper's own fits) is `none`: the nominal
// within its tolerances explains it, and the tolerance fit finds the shift. Measured from the nominal exactly
// (Tolerances::none) the same data name fpam_params, so the gap is real, only within tolerance.
TEST_F(DiagnosisTest, AVariationWithinTheTolerancesIsNone) {
  SOFTWRIST_SKIP_END_TO_END_UNDER_SANITIZERS();
  sim::DeviceDescription device = paper_device();
  SyntheticDevice real{.device = device};
  std::vector<physics::FpamTableRow> rows = device.fpam.rows();
  for (auto& row : rows) {
    row.radius *= 1.02;
    row.max_contraction -= 0.008;
  }
  real.device.fpam = physics::FpamParameters::Table(rows, device.fpam.fabric());
  write_synthetic_data(real, {.trajectory_s = 12.0}, dir_ / "real");
  const Diagnosis within = diagnose(load_real_data(dir_ / "real"), device, engine_, {.bootstrap = 100});
  EXPECT_EQ(within.verdict, "none") << within.reason;
  EXPECT_NE(within.reason.find("within its tolerances"), std::string::npos) << within.reason;
  std::map<std::string, double> fitted(within.tolerance.params.begin(), within.tolerance.params.end());
  EXPECT_NEAR(fitted.at("fpam_params.r0_scale"), 1.02, 0.005);
  EXPECT_NEAR(fitted.at("fpam_params.eps_max_shift"), -0.008, 0.002);
  EXPECT_GT(within.tolerance.heldout_error_as_placed, 1.0);

  const Diagnosis exact =
      diagnose(load_real_data(dir_ / "real"), device, engine_, {.bootstrap = 100, .tolerances = Tolerances::none()});
  EXPECT_EQ(exact.verdict, "fpam_params") << exact.reason;
  EXPECT_TRUE(exact.tolerance.params.empty());
}

// Each muscle has its own tolerances (tolerance.h): the ulnar muscle's hand anchor 2 mm nearer the wrist (of Table
// RoM's d2 = 1 cm) shows as placed, is within them (no factor shared by the muscles could say so), and the fit finds
// it.
TEST_F(DiagnosisTest, OneMusclesAnchorWithinItsToleranceIsNone) {
  SOFTWRIST_SKIP_END_TO_END_UNDER_SANITIZERS();
  sim::DeviceDescription device = paper_device();
  SyntheticDevice real{.device = device};
  real.device.muscles[sim::kUlnar].placement.d2 -= 0.002;
  write_synthetic_data(real, {.trajectory_s = 12.0}, dir_ / "real");
  const Diagnosis exact =
      diagnose(load_real_data(dir_ / "real"), device, engine_, {.bootstrap = 100, .tolerances = Tolerances::none()});
  // It shows as placed: a trial keeps a gap (2.4 noise units: `unexplained` while contradiction_gap was 1.5, `none`
  // at 3, below the evidence of an effect outside the catalogue, which a 2 mm shift is not).
  ASSERT_TRUE(std::ranges::any_of(exact.trials, [](const TrialGap& t) { return t.gap; }))
      << "the shifted anchor must show as placed: " << exact.reason;
  const Diagnosis within = diagnose(load_real_data(dir_ / "real"), device, engine_, {.bootstrap = 100});
  EXPECT_EQ(within.verdict, "none") << within.reason;
  std::map<std::string, double> fitted(within.tolerance.params.begin(), within.tolerance.params.end());
  const double d2_cm = 100.0 * device.muscles[sim::kUlnar].placement.d2;
  // Nearer the wrist, by at least half the shift: the anchor's d2 trades with its w2 and the muscle's L0, which the
  // data tell apart only partly, and the fit ends beyond the truth, at the box's edge or near it (0.715 cm with every
  // other held angle of the sweep held out, 0.700 cm with the checkerboard; the real anchor at 0.8 cm, the nominal 1).
  EXPECT_LT(fitted.at("model.ulnar.d2_cm"), d2_cm - 0.1);
  EXPECT_GE(fitted.at("model.ulnar.d2_cm"), d2_cm - 0.3 - 1e-9);  // the 3 mm tolerance
  // The flexor's anchor, placed as the nominal, trades with its L0 alike: differenced on coarse replays (Fidelity)
  // the fit ends at d2 8.351 cm and L0 32.06 cm with a training error of 0.75838, differenced on fine ones at 8.301
  // and 31.99 cm with 0.75854 (d2 8.30 cm placed). Within the same 1 mm.
  EXPECT_NEAR(fitted.at("model.flexor.d2_cm"), 100.0 * device.muscles[sim::kFlexor].placement.d2, 0.1);
}

// Each muscle's wrist radius is a tolerance of its own (tolerance_fit.cc): on the independent device's placement, where
// every muscle wraps, the flexor's radius 4.5 % larger and the extensor's 4.5 % smaller than placed (within the 5 %
// each, and no scale shared by them could say so). The fit moves each its own way, and wrap_geometry's base (the
// tolerances without its own) holds every radius at the nominal, so that the effect takes its whole value. (The
// verdict is not what changed: one shared scale with the anchors and rest lengths read `none` here too.)
TEST_F(DiagnosisTest, EachMusclesWristRadiusIsAToleranceOfItsOwn) {
  SOFTWRIST_SKIP_END_TO_END_UNDER_SANITIZERS();
  const sim::DeviceDescription nominal =
      sim::load_device(fs::path(SOFTWRIST_SOURCE_DIR) / "experiments/independent_device/prototype.json");
  SyntheticDevice real{.device = nominal};
  real.device.muscles[sim::kFlexor].wrist_radius *= 1.045;
  real.device.muscles[sim::kExtensor].wrist_radius *= 0.955;
  write_synthetic_data(real, {.trajectory_s = 12.0}, dir_ / "real");
  const DiagnosisOptions options{.bootstrap = 100};
  Diagnosis d = diagnose(load_real_data(dir_ / "real"), nominal, engine_, options);
  EXPECT_EQ(d.verdict, "none") << d.reason;
  std::map<std::string, double> fitted(d.tolerance.params.begin(), d.tolerance.params.end());
  EXPECT_FALSE(fitted.contains("wrap_geometry.wrist_radius_scale"));
  const double flexor_cm = 100.0 * nominal.muscles[sim::kFlexor].wrist_radius;
  const double extensor_cm = 100.0 * nominal.muscles[sim::kExtensor].wrist_radius;
  EXPECT_NEAR(fitted.at("model.flexor.rw_cm"), 1.045 * flexor_cm, 0.05);
  EXPECT_LT(fitted.at("model.extensor.rw_cm"), extensor_cm - 0.05);

  const GapProblem problem(d.prepared, engine_);
  const ModelVariant base = within_tolerances_without(problem, ModelVariant{.device = nominal}, options, d.tolerance,
                                                      std::array{EffectId::kWrapGeometry});
  for (std::size_t m = 0; m < 4; ++m)
    EXPECT_EQ(base.device.muscles[m].wrist_radius, nominal.muscles[m].wrist_radius) << sim::kMuscleNames[m];
  // The other tolerances stay where their fit left them.
  EXPECT_NEAR(100.0 * base.device.muscles[sim::kExtensor].placement.d2, fitted.at("model.extensor.d2_cm"), 1e-9);
}

// Each muscle's own fPAM can be a tolerance of its own (Tolerances::muscle_r0_fraction, muscle_eps_max; off by
// default): on the independent device's placement, the extensor's r0 1.8 % larger and the flexor's 1.8 % smaller than
// the table's (within 2 % each; the table's own scale, shared by all, cannot say so). Freed, each muscle has its knobs,
// the device reads `none`, and fpam_params' base (the tolerances without its own) holds every muscle at the table.
// Where each ends is not asserted: the fit trades a muscle's r0 against its L0, anchors and wrist radius.
TEST_F(DiagnosisTest, EachMusclesOwnFpamCanBeAToleranceOfItsOwn) {
  SOFTWRIST_SKIP_END_TO_END_UNDER_SANITIZERS();
  const sim::DeviceDescription nominal =
      sim::load_device(fs::path(SOFTWRIST_SOURCE_DIR) / "experiments/independent_device/prototype.json");
  SyntheticDevice real{.device = nominal};
  real.device.muscles[sim::kExtensor].fpam_radius_scale = 1.018;
  real.device.muscles[sim::kFlexor].fpam_radius_scale = 0.982;
  write_synthetic_data(real, {.trajectory_s = 12.0}, dir_ / "real");
  DiagnosisOptions options{.bootstrap = 100};
  options.tolerances.muscle_r0_fraction = 0.02;
  options.tolerances.muscle_eps_max = 0.009;
  Diagnosis d = diagnose(load_real_data(dir_ / "real"), nominal, engine_, options);
  EXPECT_EQ(d.verdict, "none") << d.reason;
  std::map<std::string, double> fitted(d.tolerance.params.begin(), d.tolerance.params.end());
  for (const char* muscle : {"flexor", "extensor", "ulnar", "radial"}) {
    EXPECT_NEAR(fitted.at(fmt::format("model.{}.r0_scale", muscle)), 1.0, 0.02 + 1e-12) << muscle;
    EXPECT_NEAR(fitted.at(fmt::format("model.{}.eps_max_shift", muscle)), 0.0, 0.009 + 1e-12) << muscle;
  }

  const GapProblem problem(d.prepared, engine_);
  const ModelVariant base = within_tolerances_without(problem, ModelVariant{.device = nominal}, options, d.tolerance,
                                                      std::array{EffectId::kFpamParams});
  for (std::size_t m = 0; m < 4; ++m) {
    EXPECT_EQ(base.device.muscles[m].fpam_radius_scale, 1.0) << sim::kMuscleNames[m];
    EXPECT_EQ(base.device.muscles[m].fpam_max_contraction_shift, 0.0) << sim::kMuscleNames[m];
  }
  // Off by default: no muscle has such a knob.
  const Diagnosis by_default = diagnose(load_real_data(dir_ / "real"), nominal, engine_, {.bootstrap = 100});
  for (const auto& [name, value] : by_default.tolerance.params)
    EXPECT_FALSE(name.starts_with("model.") && name.ends_with("_scale")) << name << " (" << by_default.verdict << ")";
}

// The paper's device with an fPAM 10 % narrower at every pressure (3 % is within the r0 tolerance).
SyntheticDevice narrower_fpam_device(const sim::DeviceDescription& device) {
  SyntheticDevice real{.device = device};
  std::vector<physics::FpamTableRow> rows = device.fpam.rows();
  for (auto& row : rows) row.radius *= 0.9;
  real.device.fpam = physics::FpamParameters::Table(rows, device.fpam.fabric());
  return real;
}

// Beyond its tolerance an effect is still named, with its whole value: the effects are fitted from the nominal as
// placed; the tolerances only decide which trials have a gap.
TEST_F(DiagnosisTest, BeyondItsToleranceAnEffectIsNamedWithItsWholeValue) {
  SOFTWRIST_SKIP_END_TO_END_UNDER_SANITIZERS();
  const sim::DeviceDescription device = paper_device();
  const Diagnosis d = run(narrower_fpam_device(device), device);
  ASSERT_EQ(d.verdict, "fpam_params") << d.reason;
  std::map<std::string, double> fitted(d.tolerance.params.begin(), d.tolerance.params.end());
  EXPECT_LT(fitted.at("fpam_params.r0_scale"), 0.98);  // the tolerance fit went towards it, and not far enough
  EXPECT_NEAR(param(d.combination.front(), "r0_scale"), 0.9, 0.01);
}

// The experimental ranking beyond the tolerances (DiagnosisOptions::rank_beyond_tolerances): every effect fitted on top
// of them, ranked by the training error it leaves; the same fPAM 10 % narrower is the leader, refitted jointly with
// the tolerances to its whole value, and its share of the held-out gap is measured against the tolerances but its own.
TEST_F(DiagnosisTest, RankedBeyondTheTolerancesTheEffectLeadsWithItsWholeValue) {
  SOFTWRIST_SKIP_END_TO_END_UNDER_SANITIZERS();
  const sim::DeviceDescription device = paper_device();
  write_synthetic_data(narrower_fpam_device(device), {.trajectory_s = 12.0}, dir_ / "real");
  const Diagnosis d =
      diagnose(load_real_data(dir_ / "real"), device, engine_, {.bootstrap = 100, .rank_beyond_tolerances = true});
  ASSERT_EQ(d.verdict, "fpam_params") << d.reason;
  ASSERT_FALSE(d.beyond_tolerance.empty());
  for (std::size_t i = 1; i < d.beyond_tolerance.size(); ++i)
    EXPECT_LE(d.beyond_tolerance[i - 1].train_error_with_effect, d.beyond_tolerance[i].train_error_with_effect);
  const auto& lead = d.beyond_tolerance.front();
  EXPECT_TRUE(lead.joint);
  EXPECT_GE(lead.explained_in_acted_on, 0.6);
  EXPECT_NEAR(param(d.combination.front(), "r0_scale"), 0.9, 0.01);
  EXPECT_EQ(d.effects.front().name, "fpam_params");
}

// The fit from the nominal within its tolerances (EffectBase::kWithinTolerances): each
// effect starts from the tolerance fit with its own tolerance parameters back at the nominal, so the same fPAM 10 %
// narrower is named, fitted beyond its tolerance (on the whole tolerance fit, whose r0 went towards it, it would take
// the rest only).
TEST_F(DiagnosisTest, FittedWithinTheTolerancesTheEffectIsNamedBeyondItsOwn) {
  SOFTWRIST_SKIP_END_TO_END_UNDER_SANITIZERS();
  const sim::DeviceDescription device = paper_device();
  write_synthetic_data(narrower_fpam_device(device), {.trajectory_s = 12.0}, dir_ / "real");
  const Diagnosis d = diagnose(load_real_data(dir_ / "real"), device, engine_,
                               {.bootstrap = 100, .effect_base = EffectBase::kWithinTolerances});
  ASSERT_EQ(d.verdict, "fpam_params") << d.reason;
  // Beyond its 3 % box, but not all the way: the other tolerances, held where their fit ended, took part of it when
  // the fPAM's own could not (r0 x 0.952 for the true 0.9; a joint refit, rank_beyond_tolerances, gets 0.9).
  const double r0 = param(d.combination.front(), "r0_scale");
  EXPECT_LT(r0, 0.97);
  EXPECT_GT(r0, 0.89);
  // Its share counts only what it closes beyond its own box (measure_explained): from 0.97 to 0.952, a third of the
  // gap. Fitted jointly with the tolerances (Diagnosis::leader_beyond_tolerance), it takes most of what they leave.
  EXPECT_LT(d.explained_fraction, 0.5);
  ASSERT_TRUE(d.leader_beyond_tolerance.has_value());
  EXPECT_GE(d.leader_beyond_tolerance->explained_fraction, 0.6) << d.reason;
  // The combination starts from the single fits' leader, on the base that leader was fitted on.
  EXPECT_EQ(d.combination.front().id, d.effects.front().id);
  // The effects with no tolerance parameters of their own (the hysteresis, the IMUs) start where the whole tolerance
  // fit ended, with less of the gap left than the fPAM's own base leaves.
  const double within = fit_of(d, EffectId::kHysteresis).heldout_error_before;
  EXPECT_DOUBLE_EQ(fit_of(d, EffectId::kImuBias).heldout_error_before, within);
  EXPECT_LT(within, fit_of(d, EffectId::kFpamParams).heldout_error_before);
}

// An effect's start that cannot be built on the tolerances as fitted (seed 4 of the independent benchmark: a wrap
// surface fitted from the nominal as placed, on anchors the tolerance fit had moved, held a mount inside it, and the
// whole diagnosis stopped with "least squares: the start is infeasible"): the joint fit starts from the effect's
// neutral value on the tolerances as fitted instead, and ends no worse than that start. Both the call the verdict
// makes (no second start) and the ranking's (a second start from the nominal) are checked.
TEST_F(DiagnosisTest, AnEffectStartBeyondTheGeometryFallsBackToItsNeutralValue) {
  SOFTWRIST_SKIP_END_TO_END_UNDER_SANITIZERS();
  const sim::DeviceDescription device = paper_device();
  write_synthetic_data(narrower_fpam_device(device), {.trajectory = false}, dir_ / "real");  // a gap to fit
  const DiagnosisOptions options{.effects = {EffectId::kPassiveWrist}, .bootstrap = 20};
  Diagnosis d = diagnose(load_real_data(dir_ / "real"), device, engine_, options);
  ASSERT_FALSE(d.tolerance.params.empty());
  const GapProblem problem(d.prepared, engine_);
  const ModelVariant nominal{.device = device};
  // The fallback start: the tolerances as fitted with wrap_geometry's own back at the nominal, the effect neutral.
  const ModelVariant fallback =
      within_tolerances_without(problem, nominal, options, d.tolerance, std::array{EffectId::kWrapGeometry});
  const double fallback_error = problem.training_error(problem.evaluate(fallback, true));
  ASSERT_LT(fallback_error, kInfeasible);
  // A wrap surface within the catalogue's ranges that neither the nominal's geometry nor the fitted one accepts.
  const EffectSpec& wrap = effect_spec(EffectId::kWrapGeometry);
  const auto builds = [](ModelVariant v, const std::vector<double>& values) {
    try {
      apply_effect(EffectId::kWrapGeometry, values, v);
      return true;
    } catch (const std::exception&) {
      return false;
    }
  };
  std::vector<double> unbuildable;
  for (int corner = 0; corner < (1 << wrap.parameters.size()) && unbuildable.empty(); ++corner) {
    std::vector<double> values;
    for (std::size_t i = 0; i < wrap.parameters.size(); ++i)
      values.push_back((corner >> i) & 1 ? wrap.parameters[i].upper : wrap.parameters[i].lower);
    if (!builds(nominal, values) && !builds(fallback, values)) unbuildable = values;
  }
  ASSERT_FALSE(unbuildable.empty()) << "every corner of wrap_geometry's ranges builds: the test needs another start";
  for (const bool second_start : {false, true}) {
    const JointFit fit =
        fit_effect_within_tolerances(problem, nominal, options, d.tolerance, EffectId::kWrapGeometry, unbuildable,
                                     second_start ? std::span<const double>(unbuildable) : std::span<const double>());
    EXPECT_LE(problem.training_error(problem.evaluate(fit.variant, true)), fallback_error * (1.0 + 1e-9))
        << (second_start ? "with" : "without") << " a second start";
  }
}

// The default (EffectBase::kBetterOfBoth): each effect fitted from the nominal as placed and from the nominal within
// its tolerances, the fit that predicts the held-out data better kept. A device whose hand anchors and rest lengths
// sit within their tolerances of the placement file, with a fabric hysteresis besides: fitted from the nominal as
// placed, the hysteresis competes with the placement's scatter and the corrected model misses the held-out data by
// 2.54 noise units (4.45 before extensions were searched also where one trial keeps min_gap, commit 2c77788, the
// relaxed wrist's among them); fitted within the tolerances, it takes what they leave, 1.63. (Its fraction comes
// out 0.029 for the true 0.05 there, against 0.048 as placed: the relaxed wrist's damping, held at its tolerance's
// edge, took part of the loss. Docs/diagnosis.md, Known limits.)
TEST_F(DiagnosisTest, FromTheBetterOfBothBasesTheCorrectedModelPredictsBetter) {
  SOFTWRIST_SKIP_END_TO_END_UNDER_SANITIZERS();
  const sim::DeviceDescription device = paper_device();
  SyntheticDevice real{.device = device, .hysteresis = 0.05};
  const double sign[] = {1.0, -1.0, -1.0, 1.0};
  for (std::size_t i = 0; i < real.device.muscles.size(); ++i) {
    real.device.muscles[i].placement.d2 += 0.0025 * sign[i];  // within the 3 mm anchor tolerance
    real.device.muscles[i].rest_length -= 0.0015 * sign[i];   // within the 2 mm rest length tolerance
  }
  write_synthetic_data(real, {.trajectory_s = 12.0}, dir_ / "real");
  const auto run_from = [&](EffectBase base) {
    return diagnose(load_real_data(dir_ / "real"), device, engine_, {.bootstrap = 100, .effect_base = base});
  };
  const Diagnosis as_placed = run_from(EffectBase::kAsPlaced), better = run_from(EffectBase::kBetterOfBoth);
  ASSERT_EQ(as_placed.verdict, "hysteresis") << as_placed.reason;
  ASSERT_EQ(better.verdict, "hysteresis") << better.reason;
  const EffectFit& f = fit_of(better, EffectId::kHysteresis);
  EXPECT_TRUE(f.within_tolerances);
  EXPECT_EQ(f.base_parameters, better.tolerance.params.size());
  EXPECT_FALSE(fit_of(as_placed, EffectId::kHysteresis).within_tolerances);
  EXPECT_GT(param(f, "fraction"), 0.0);
  EXPECT_LT(better.heldout_corrected, 0.75 * as_placed.heldout_corrected)
      << better.heldout_corrected << " against " << as_placed.heldout_corrected;
}

// A regulator's dead time and an IMU's latency delay the replayed angles alike; the measured pressures
// (p_<muscle>_kpa, as the bridge logs them) show which one it is: only the regulator delays the pressures.
TEST_F(DiagnosisTest, MeasuredPressuresTellRegulatorDeadTimeFromImuLatency) {
  const SyntheticPlan trajectory_only{
      .torque_sweep = false, .range_of_motion = false, .tensile = false, .trajectory_s = 12.0};
  const std::vector<EffectId> both = {EffectId::kRegulatorLag, EffectId::kImuBias};
  {
    const auto d = run({.device = paper_device(), .regulator_dead_time = 0.08}, paper_device(), both, trajectory_only);
    ASSERT_EQ(d.verdict, "regulator_lag") << d.reason;
    EXPECT_NEAR(param(d.combination.front(), "dead_time_s"), 0.08, 0.01);
    // The second order that could trade off against the dead time is not taken (ParameterSpec::extension).
    EXPECT_FALSE(fit_of(d, EffectId::kRegulatorLag).extended);
    EXPECT_LT(fit_of(d, EffectId::kImuBias).shrink_fraction, fit_of(d, EffectId::kRegulatorLag).shrink_fraction - 0.1);
    bool pressure_gap = false;
    for (const auto& t : d.trials) pressure_gap = pressure_gap || (t.unit == "kPa" && t.significant);
    EXPECT_TRUE(pressure_gap);
  }
  {
    fs::remove_all(dir_ / "real");
    const auto d = run({.device = paper_device(), .imu_latency = 0.08}, paper_device(), both, trajectory_only);
    ASSERT_EQ(d.verdict, "imu_bias") << d.reason;
    EXPECT_NEAR(param(d.combination.front(), "latency_s"), 0.08, 0.01);
    for (const auto& t : d.trials) {
      if (t.unit == "kPa") {
        EXPECT_FALSE(t.significant) << t.experiment << " p = " << t.p_value;
      }
    }
  }
}

// A smaller wrist only changes the torque while the flexor wraps (Eqn. tau2: moment arm r_w); the localisation
// must put the gap there and not in the straight-line regime.
TEST_F(DiagnosisTest, WristRadiusChangeIsLocalisedInTheWrappingRange) {
  SyntheticDevice real{.device = paper_device()};
  for (auto& m : real.device.muscles) m.wrist_radius *= 0.85;
  const Diagnosis d = run(real, paper_device(), {EffectId::kWrapGeometry},
                          {.range_of_motion = false, .tensile = false, .trajectory = false});
  const LocalizationEntry* first_angle = nullptr;
  bool wrapping_significant = false, straight_significant = true;
  for (const auto& e : d.localization) {
    if (!first_angle && e.where.starts_with("flexor angle")) first_angle = &e;
    if (e.where == "wrapping regime") wrapping_significant = e.significant;
    if (e.where == "straight regime") straight_significant = e.significant;
  }
  ASSERT_NE(first_angle, nullptr);
  EXPECT_NE(first_angle->where.find("(wrapping)"), std::string::npos) << first_angle->where;
  EXPECT_TRUE(wrapping_significant);
  EXPECT_FALSE(straight_significant);
  EXPECT_EQ(d.verdict, "wrap_geometry");
}

TEST_F(DiagnosisTest, BadFilesAreReportedOneByOneAndTheRestIsDiagnosed) {
  write_synthetic_data({.device = paper_device()}, {.range_of_motion = false, .tensile = false, .trajectory = false},
                       dir_ / "real");
  const auto write = [&](const fs::path& path, const std::string& text) {
    fs::create_directories(path.parent_path());
    std::ofstream(path) << text;
  };
  // A log whose CSV has a NaN, one with a column missing, a CSV without a sidecar, a log of the wrong kind.
  fs::copy(dir_ / "real/torque_sweep", dir_ / "real/nan_sweep");
  {
    std::ifstream in(dir_ / "real/nan_sweep/trials.csv");
    std::string text((std::istreambuf_iterator<char>(in)), {});
    const auto cell = text.find("\n0,flexor,") + 10;
    text.replace(cell, text.find(',', cell) - cell, "nan");
    std::ofstream(dir_ / "real/nan_sweep/trials.csv") << text;
  }
  fs::copy(dir_ / "real/torque_sweep", dir_ / "real/short_sweep");
  write(dir_ / "real/short_sweep/trials.csv", "repetition,muscle,angle_deg,pressure_kpa\n0,flexor,0,34\n");
  write(dir_ / "real/loose/mine.csv", "angle_deg,torque_nm\n0,1\n");
  const Diagnosis d = diagnose(load_real_data(dir_ / "real"), paper_device(), engine_, {.bootstrap = 50});
  ASSERT_EQ(d.problems.size(), 3u);
  std::string all;
  for (const auto& p : d.problems) all += p.file + ": " + p.reason + "\n";
  EXPECT_NE(all.find("nan_sweep/trials.csv:2: angle_deg"), std::string::npos) << all;
  EXPECT_NE(all.find("short_sweep"), std::string::npos) << all;
  EXPECT_NE(all.find("softwrist import"), std::string::npos) << all;
  ASSERT_EQ(d.trials.size(), 1u);
  EXPECT_EQ(d.verdict, "none");
}

TEST_F(DiagnosisTest, ReplayBeyondTheRegulatorsIsReportedNotRun) {
  write_synthetic_data({.device = paper_device()}, {.range_of_motion = false, .tensile = false, .trajectory = false},
                       dir_ / "real");
  sim::DeviceDescription nominal = paper_device();
  nominal.regulator.max_pressure = 100e3;  // the sweep's 103 and 137 kPa are beyond it
  EXPECT_THROW(
      {
        try {
          diagnose(load_real_data(dir_ / "real"), nominal, engine_, {.bootstrap = 50});
        } catch (const std::runtime_error& e) {
          EXPECT_NE(std::string(e.what()).find("no trial left"), std::string::npos) << e.what();
          throw;
        }
      },
      std::runtime_error);
}

// Section Torque applied by the exosuit measures the flexor's torque "to the relaxed wrist": a sensor on the hand
// plate reads the muscle's torque plus the relaxed wrist's, -k angle. Undeclared, that is a gap nothing of the muscle
// closes; declared at import (--torque-includes muscle+passive_wrist), the nominal model has none; and a wrist 2.5
// times stiffer than the nominal's, declared, is named passive_wrist (which now acts on such sweeps).
TEST_F(DiagnosisTest, SweepReadingTheRelaxedWristToo) {
  const sim::DeviceDescription nominal = paper_device();
  const auto diagnose_sweep = [&](double stiffness_scale, const std::string& includes) {
    SyntheticDevice real{.device = nominal};
    real.device.wrist.stiffness_fe *= stiffness_scale;
    const fs::path synth = dir_ / fmt::format("synth_{}", stiffness_scale);
    write_synthetic_data(real, {.range_of_motion = false, .tensile = false, .trajectory = false}, synth);
    const io::CsvTable sweep = io::CsvTable::Read(synth / "torque_sweep/trials.csv");
    std::string csv = "angle_deg,pressure_kpa,torque_nm,repetition\n";
    for (std::size_t r = 0; r < sweep.row_count(); ++r) {
      const double angle_deg = sweep.number(r, sweep.column("angle_deg"));
      const double relaxed_wrist = -real.device.wrist.stiffness_fe * angle_deg * M_PI / 180.0;
      csv += fmt::format("{},{},{},{}\n", angle_deg, sweep.number(r, sweep.column("pressure_kpa")),
                         sweep.number(r, sweep.column("torque_nm")) + relaxed_wrist,
                         sweep.cell(r, sweep.column("repetition")));
    }
    const fs::path user = dir_ / fmt::format("user_{}_{}", stiffness_scale, includes);
    fs::create_directories(user);
    std::ofstream(user / "sweep.csv") << csv;
    import_csv(user / "sweep.csv", user / "log", {.kind = "torque-sweep", .torque_includes = includes});
    fs::remove(user / "sweep.csv");
    return diagnose(load_real_data(user), nominal, engine_, {.bootstrap = 100});
  };
  const Diagnosis undeclared = diagnose_sweep(1.0, "");
  EXPECT_NE(undeclared.verdict, "none") << undeclared.reason;
  EXPECT_TRUE(undeclared.trials.at(0).gap);
  const Diagnosis declared = diagnose_sweep(1.0, "muscle+passive_wrist");
  EXPECT_EQ(declared.verdict, "none") << declared.reason;
  const Diagnosis stiffer = diagnose_sweep(2.5, "muscle+passive_wrist");
  EXPECT_EQ(stiffer.verdict, "passive_wrist") << stiffer.reason;
  EXPECT_NEAR(param(fit_of(stiffer, EffectId::kPassiveWrist), "stiffness_scale"), 2.5, 0.1);
}

// Issue 19's two rigs: the torque sweep from the torque rig (Table torque_measurement_parameters, the paper's device)
// and the range of motion and trajectory from the prototype (Table RoM), whose mounts stretch alike (the paper's K1,
// K2). Each log names its rig's placement file; one diagnosis of the one directory recovers the series stiffness once,
// from both rigs' data, and the corrected model fits both.
TEST_F(DiagnosisTest, TwoRigsInOneDirectoryShareTheMountStiffness) {
  SOFTWRIST_SKIP_END_TO_END_UNDER_SANITIZERS();
  const auto rigid = [&](sim::DeviceDescription device, const std::string& name) {
    device.stretch_mode = physics::StretchMode::kNone;
    std::ofstream(dir_ / name) << sim::device_to_json(device);
    return dir_ / name;
  };
  const fs::path torque_rig = rigid(paper_device(), "torque_rig_rigid.json");
  const fs::path prototype = rigid(sim::rom_device(), "prototype_rigid.json");
  // Both real rigs stretch with the paper's K1, K2 (rom_device carries the torque rig's, the only K the paper gives).
  write_synthetic_data({.device = paper_device()}, {.range_of_motion = false, .tensile = false, .trajectory = false},
                       dir_ / "real/torque_rig");
  write_synthetic_data({.device = sim::rom_device()}, {.torque_sweep = false, .tensile = false, .trajectory_s = 12.0},
                       dir_ / "real/prototype");
  const auto name_rig = [](const fs::path& sidecar, const fs::path& placement) {
    nlohmann::json json = nlohmann::json::parse(std::ifstream(sidecar));
    json["config"]["placement"] = placement.string();
    std::ofstream(sidecar) << json.dump(2);
  };
  for (const fs::path& sidecar : {dir_ / "real/torque_rig/torque_sweep/trials.json"}) name_rig(sidecar, torque_rig);
  for (const char* log : {"range_of_motion", "trajectory"})
    name_rig(dir_ / "real/prototype" / log / "trials.json", prototype);

  // The default model is neither rig: every log names its own.
  const Diagnosis d = diagnose(load_real_data(dir_ / "real"), sim::rom_device(), engine_, {.bootstrap = 100});
  ASSERT_EQ(d.verdict, "mount_stretch") << d.reason;
  // The rigid nominal's misfit hides the routing as placed (the planar one a little lower): both routings are
  // diagnosed, and the spatial one the data were simulated with fits far better once the mounts stretch; its nominal
  // within the tolerances predicts the held-out part better too (RoutingBy::kNominalWithinTolerances would keep it).
  ASSERT_EQ(d.routing_heldout_error.size(), 2u);
  EXPECT_EQ(d.routing, sim::Routing::kSpatial);
  ASSERT_EQ(d.routing_heldout_error_nominal.size(), 2u);
  EXPECT_EQ(d.routing_heldout_error_nominal[0].first, sim::Routing::kPlanar);  // the lower as placed, tried first
  EXPECT_LT(d.routing_heldout_error_nominal[1].second, 0.5 * d.routing_heldout_error_nominal[0].second);  // 1.4, 5.1
  EXPECT_NEAR(param(d.combination.front(), "K_series_n_per_cm2"), 30.16, 1.5);  // as in the paper's case above
  ASSERT_TRUE(d.corrected.has_value());
  EXPECT_EQ(d.corrected->rigs.size(), 2u);
  for (const auto& t : d.trials) EXPECT_LT(t.excess_corrected, 1.0) << t.experiment;
  // The joint refit (a calibration's) replays each trial on its own rig too: it started from the nominal's device
  // alone, where no trial that names a rig could be replayed, and stopped with "least squares: the start is
  // infeasible".
  const Diagnosis refitted =
      diagnose(load_real_data(dir_ / "real"), sim::rom_device(), engine_,
               {.effects = {EffectId::kMountStretch}, .bootstrap = 20, .joint_refit_evaluations = 20});
  ASSERT_EQ(refitted.verdict, "mount_stretch") << refitted.reason;
  EXPECT_NEAR(param(refitted.combination.front(), "K_series_n_per_cm2"), 30.16, 1.5);
  ASSERT_TRUE(refitted.corrected.has_value());
  EXPECT_EQ(refitted.corrected->rigs.size(), 2u);
}

// A fabric muscle pulls harder while it is being stretched than while it shortens (Fig. TensileTest's loops), so a
// torque sweep whose held angles are reached from both sides (repetition 0 towards flexion, repetition 1 back) shows
// hysteresis as the tensile rig does. The sweep's order is read from the log; hysteresis, fitted by the whole
// catalogue on a sweep alone, is named and its fraction recovered. (The data scale the synthetic torque by 1 -+ h as
// the catalogue's form does: this checks that the order reaches the replay; the independent generator's friction
// forms are diagnosed by diagnose-bench --generator independent.)
TEST_F(DiagnosisTest, SweepReachedFromBothSidesShowsHysteresis) {
  const sim::DeviceDescription nominal = paper_device();
  write_synthetic_data({.device = nominal}, {.range_of_motion = false, .tensile = false, .trajectory = false},
                       dir_ / "synth");
  const io::CsvTable sweep = io::CsvTable::Read(dir_ / "synth/torque_sweep/trials.csv");
  struct Row {
    double angle_deg, kpa, torque;
    int rep;
  };
  std::vector<Row> rows;
  for (std::size_t r = 0; r < sweep.row_count(); ++r) {
    rows.push_back({sweep.number(r, sweep.column("angle_deg")), sweep.number(r, sweep.column("pressure_kpa")),
                    sweep.number(r, sweep.column("torque_nm")),
                    static_cast<int>(sweep.number(r, sweep.column("repetition")))});
  }
  // Repetition 0 towards flexion (the flexor shortens: it pulls 1 - h), repetition 1 back (it is stretched: 1 + h).
  constexpr double h = 0.08;
  std::string csv = "angle_deg,pressure_kpa,torque_nm,repetition\n";
  for (int rep : {0, 1}) {
    std::vector<Row> these;
    for (const Row& row : rows) {
      if (row.rep == rep) these.push_back(row);
    }
    if (rep == 1) std::reverse(these.begin(), these.end());
    for (const Row& row : these) {
      csv += fmt::format("{},{},{},{}\n", row.angle_deg, row.kpa, row.torque * (rep == 0 ? 1.0 - h : 1.0 + h), rep);
    }
  }
  fs::create_directories(dir_ / "user");
  std::ofstream(dir_ / "sweep.csv") << csv;
  import_csv(dir_ / "sweep.csv", dir_ / "user/sweep", {.kind = "torque-sweep"});
  const Diagnosis d = diagnose(load_real_data(dir_ / "user"), nominal, engine_, {.bootstrap = 100});
  EXPECT_EQ(d.verdict, "hysteresis") << d.reason;
  EXPECT_NEAR(param(fit_of(d, EffectId::kHysteresis), "fraction"), h, 0.01);
}

// A sweep's direction of approach comes from the log's order (real_data.cc, set_sweep_motion), and measured held angles
// scatter: one reading 3.5 deg off its set angle's others is no step out and back, so a sweep whose angles all went up
// stays "one way" (motion 0, no evidence of hysteresis), as before a jittered reading of the catalogue's rig
// (clustered apart at 2.5 deg) made it "both ways". The same sweep with its second repetition run back down is read
// both ways, each held angle from the side it was reached from, the jittered reading's too.
TEST_F(DiagnosisTest, AJitteredHeldAngleIsNoReversalOfTheSweep) {
  const std::vector<double> set_angles = {-45.0, -22.5, 0.0, 22.5, 45.0};
  const auto motions = [&](bool second_back, const std::string& name) {
    std::string csv = "angle_deg,pressure_kpa,torque_nm,repetition\n";
    for (int rep : {0, 1}) {
      std::vector<double> order = set_angles;
      if (rep == 1 && second_back) std::reverse(order.begin(), order.end());
      for (double angle : order) {
        for (int k = 0; k < 4; ++k) {
          const double jitter = rep == 0 && angle == 0.0 && k == 2 ? 3.5 : (k % 2 == 0 ? -0.3 : 0.3);
          csv += fmt::format("{},{},{},{}\n", angle + jitter, 34.0 * k, 0.5 + 0.01 * angle, rep);
        }
      }
    }
    std::ofstream(dir_ / (name + ".csv")) << csv;
    import_csv(dir_ / (name + ".csv"), dir_ / name / "sweep", {.kind = "torque-sweep"});
    std::map<std::pair<int, double>, std::set<int>> by_held_angle;  // [repetition, set angle] -> motions read
    for (const Trial& t : load_real_data(dir_ / name).trials) {
      for (const SweepPoint& p : t.sweep)
        by_held_angle[{p.repetition, 22.5 * std::round(units::rad_to_deg(p.angle) / 22.5)}].insert(p.motion);
    }
    return by_held_angle;
  };
  const auto one_way = motions(false, "up");
  ASSERT_EQ(one_way.size(), 10u);
  for (const auto& [held, read] : one_way) EXPECT_EQ(read, std::set<int>{0}) << held.first << " " << held.second;
  const auto both_ways = motions(true, "up_and_back");
  ASSERT_EQ(both_ways.size(), 10u);
  for (const auto& [held, read] : both_ways) {
    const auto [repetition, angle] = held;
    const bool first = angle == (repetition == 0 ? set_angles.front() : set_angles.back());
    EXPECT_EQ(read, std::set<int>{first ? 0 : (repetition == 0 ? 1 : -1)}) << repetition << " " << angle;
  }
}

// The replay groups a sweep's readings by set angle (replay.cc, prepare_sweep: its noise groups, bootstrap units and
// held-out checkerboard) by the same rule as the direction of approach: the reading 3.5 deg off its set angle's others
// is a cluster of its own at 2.5 deg, and still that set angle; set angles 22.5 deg apart stay apart, and so do two
// 6 deg apart (beyond the 5 deg rule), whatever the order of the readings.
TEST(SetAngleClusters, AJitteredReadingStaysWithItsSetAngle) {
  const std::vector<double> angles_deg = {-0.3, 22.8, -45.3, 3.5, 0.3, -44.7, 22.2, -0.3, 28.5, 28.2};
  EXPECT_EQ(clusters(angles_deg, kHeldAngleGapDeg), (std::vector<int>{1, 3, 0, 2, 1, 0, 3, 1, 4, 4}));
  EXPECT_EQ(set_angle_clusters(angles_deg), (std::vector<int>{1, 2, 0, 1, 1, 0, 2, 1, 3, 3}));
  EXPECT_TRUE(set_angle_clusters({}).empty());
}

// The fabric's hysteresis as a state of the muscles' force (physics/fpam_hysteresis.h, issue 19): a device without
// tensile tests or sweeps, only its range of motion and a trajectory, in which a fabric with h = 0.1 holds every
// muscle on its shortening branch at its limit and lags the trajectory's force. The whole catalogue names hysteresis
// from these alone, with the loop's width: angles alone do not tell a loop that scales with the pull from a dry
// friction (both widen it where the muscles work), so the fitted half width h F + min(F, F_0 + mu pi r0^2 P) is
// checked against the true 0.1 F where the muscles work: at 137 and 60 kPa, 10 % contraction.
TEST_F(DiagnosisTest, HysteresisShowsInRangeOfMotionAndTrajectoriesAlone) {
  SOFTWRIST_SKIP_END_TO_END_UNDER_SANITIZERS();
  const SyntheticPlan plan{.torque_sweep = false, .tensile = false, .trajectory_s = 12.0};
  write_synthetic_data({.device = paper_device(), .hysteresis = 0.1}, plan, dir_ / "real");
  const Diagnosis d = diagnose(load_real_data(dir_ / "real"), paper_device(), engine_, {.bootstrap = 100});
  ASSERT_EQ(d.verdict, "hysteresis") << d.reason;
  const EffectFit& f = fit_of(d, EffectId::kHysteresis);
  const physics::FpamHysteresis fitted{.fraction = param(f, "fraction"),
                                       .friction_force = param(f, "friction_n"),
                                       .pressure_friction = param(f, "pressure_friction")};
  const physics::FpamParameters& fpam = paper_device().fpam;
  for (const double kpa : {137.0, 60.0}) {
    const double pressure = units::kpa_to_pa(kpa), force = physics::fpam_force(fpam, pressure, 0.1);
    const double half_width =
        physics::hysteretic_force(fitted, force, 1.0,
                                  physics::pressure_end_force(pressure, fpam.at_pressure(pressure))) -
        force;
    EXPECT_NEAR(half_width, 0.1 * force, 0.25 * 0.1 * force) << kpa << " kPa";
  }
}

// A J-shaped fabric (physics/fpam_parameters.h: the exponential the paper fits to its 0 kPa tensile curve) pulls
// harder near full stretch on the tensile rig and on every stretched antagonist. The whole catalogue names fpam_params
// and finds the curvature, the pressure terms (r0, eps_max) left as they were.
TEST_F(DiagnosisTest, JShapedFabricIsFpamParamsWithItsCurvature) {
  SOFTWRIST_SKIP_END_TO_END_UNDER_SANITIZERS();
  sim::DeviceDescription real = paper_device();
  real.fpam = real.fpam.with_fabric({.elastic_curvature = 25.0});
  const Diagnosis d = run({.device = real}, paper_device());
  ASSERT_EQ(d.verdict, "fpam_params") << d.reason;
  const EffectFit& f = fit_of(d, EffectId::kFpamParams);
  EXPECT_NEAR(param(f, "fabric_curvature"), 25.0, 5.0);
  EXPECT_NEAR(param(f, "r0_scale"), 1.0, 0.02);
  EXPECT_NEAR(param(f, "eps_max_shift"), 0.0, 0.005);
}

// An IMU pair strapped turned by 10 deg about the forearm reads flexion partly as deviation and the other way round.
// The whole catalogue names imu_bias and finds the turn.
TEST_F(DiagnosisTest, ImuAxesTurnedAboutTheForearmAreImuBias) {
  SOFTWRIST_SKIP_END_TO_END_UNDER_SANITIZERS();
  const Diagnosis d = run({.device = paper_device(), .imu_axis_roll_deg = 10.0}, paper_device());
  ASSERT_EQ(d.verdict, "imu_bias") << d.reason;
  EXPECT_NEAR(param(fit_of(d, EffectId::kImuBias), "axis_roll_deg"), 10.0, 1.0);
}

// The wrist circle's centre off the joint (physics::WrapSurface: 5 mm towards the hand, 4 mm towards the palm): the
// flexor's path hugs a circle nearer its hand mount, the extensor's one farther from it. The whole catalogue names
// wrap_geometry and finds where the centre lies, not another radius.
TEST_F(DiagnosisTest, WristCircleOffTheJointIsWrapGeometry) {
  SOFTWRIST_SKIP_END_TO_END_UNDER_SANITIZERS();
  sim::DeviceDescription real = paper_device();
  for (std::size_t i = 0; i < real.muscles.size(); ++i) {
    real.muscles[i].wrap_surface = {.x = 0.005, .y = i == sim::kFlexor ? 0.004 : i == sim::kExtensor ? -0.004 : 0.0};
  }
  const Diagnosis d = run({.device = real}, paper_device());
  ASSERT_EQ(d.verdict, "wrap_geometry") << d.reason;
  const EffectFit& f = fit_of(d, EffectId::kWrapGeometry);
  EXPECT_NEAR(param(f, "centre_distal_mm"), 5.0, 1.5);
  EXPECT_NEAR(param(f, "centre_palmar_mm"), 4.0, 1.5);
  EXPECT_NEAR(param(f, "wrist_radius_scale"), 1.0, 0.05);
}

// A wrist surface that is not a circle (physics::WrapSurface aspect 1.5: flatter along the forearm than across it),
// on every muscle: the sweeps through the 2D law, the range of motion and trajectories through MuJoCo's equivalent
// circles. The whole catalogue names wrap_geometry and finds the aspect, an extension kept because it lowers the
// held-out error by more than one standard error.
TEST_F(DiagnosisTest, WristSurfaceNotACircleIsWrapGeometry) {
  SOFTWRIST_SKIP_END_TO_END_UNDER_SANITIZERS();
  sim::DeviceDescription real = paper_device();
  for (auto& m : real.muscles) m.wrap_surface.aspect = 1.5;
  const Diagnosis d = run({.device = real}, paper_device());
  ASSERT_EQ(d.verdict, "wrap_geometry") << d.reason;
  const EffectFit& f = fit_of(d, EffectId::kWrapGeometry);
  EXPECT_TRUE(f.extended);
  EXPECT_NEAR(param(f, "aspect_scale"), 1.5, 0.15);
}

// A wrist surface longer along the forearm and narrower across it than the nominal's circle (radius x 0.76, aspect
// 1.7, as the independent generator's elliptical_section makes it at level 1), on the independent device's
// placement, seen in a torque sweep (the search, not the tolerances, is what is tested): with the aspect stretching
// the surface along the forearm at the radius across it, no extension level reached it from the nominal's radius,
// whose ellipse would hold the hand mounts (an infeasible start), nor from the base form's optimum, a circle moved
// 4.4 mm towards the hand (unexplained, the aspect left at 1, before the extensions' levels were crossed with the
// base parameters'). The aspect now changes the shape at the semi-axes' geometric mean (effects.cc).
TEST_F(DiagnosisTest, AWristSurfaceLongAndNarrowIsWrapGeometryWithBothItsAxes) {
  SOFTWRIST_SKIP_END_TO_END_UNDER_SANITIZERS();
  const sim::DeviceDescription nominal =
      sim::load_device(fs::path(SOFTWRIST_SOURCE_DIR) / "experiments/independent_device/prototype.json");
  SyntheticDevice real{.device = nominal};
  for (auto& m : real.device.muscles) {
    m.wrist_radius *= 0.76;
    m.wrap_surface.aspect = 1.7;
  }
  write_synthetic_data(real, {.range_of_motion = false, .tensile = false, .trajectory = false}, dir_ / "real");
  const Diagnosis d =
      diagnose(load_real_data(dir_ / "real"), nominal, engine_,
               {.effects = {EffectId::kWrapGeometry}, .bootstrap = 100, .tolerances = Tolerances::none()});
  ASSERT_EQ(d.verdict, "wrap_geometry") << d.reason;
  const EffectFit& f = fit_of(d, EffectId::kWrapGeometry);
  EXPECT_TRUE(f.extended);
  EXPECT_GT(f.shrink_fraction, 0.9);
  EXPECT_NEAR(param(f, "across_scale"), 0.76, 0.03);
  // One muscle's sweep trades the aspect against the centre along the forearm (1.93 with it 5.9 mm towards the
  // elbow): longer along the forearm is what it fixes.
  EXPECT_GT(param(f, "aspect_scale"), 1.5);
}

// A regulator whose response is of second order (physics/pressure_regulator.h; tau2 = 0.06 s against the nominal's
// tau = 0.1 s, damping ratio 0.83: the rise starts late and bends like an S). The whole catalogue names regulator_lag
// and finds the second time, not only a longer first-order lag or a dead time. The trajectory steps its commands: a
// slow sinusoid shows a regulator only as a lag, which a first-order one has too.
TEST_F(DiagnosisTest, SecondOrderRegulatorIsRegulatorLag) {
  SOFTWRIST_SKIP_END_TO_END_UNDER_SANITIZERS();
  sim::DeviceDescription real = paper_device();
  real.regulator.second_order_time = 0.06;
  const Diagnosis d = run({.device = real}, paper_device(), {}, {.trajectory_s = 12.0, .trajectory_steps = true});
  ASSERT_EQ(d.verdict, "regulator_lag") << d.reason;
  const EffectFit& f = fit_of(d, EffectId::kRegulatorLag);
  EXPECT_TRUE(f.extended);
  EXPECT_NEAR(param(f, "second_order_time_s"), 0.06, 0.015);
  EXPECT_NEAR(param(f, "time_constant_s"), 0.1, 0.02);
}

// A strap in series with the mounts of the nominal's law (physics::MountStiffness::shaped_share): a linear band
// pre-tensioned to 6 N whose compliance at F_r equals the mounts' own, so that the law is neither the paper's square
// root nor one power of the pull. The whole catalogue names mount_stretch and finds the band's share and shape, an
// extension kept because it lowers the held-out error by more than one standard error.
TEST_F(DiagnosisTest, AStrapInSeriesWithThePapersMountsIsMountStretch) {
  SOFTWRIST_SKIP_END_TO_END_UNDER_SANITIZERS();
  sim::DeviceDescription real = paper_device();
  ASSERT_NE(real.stretch_mode, physics::StretchMode::kNone);
  real.mount_stiffness.forearm /= 4.0;  // twice the compliance at F_r, half of it the band's
  real.mount_stiffness.hand /= 4.0;
  real.mount_stiffness.exponent = 1.0;
  real.mount_stiffness.preload = 6.0;
  real.mount_stiffness.shaped_share = 0.5;
  const Diagnosis d = run({.device = real}, paper_device());
  ASSERT_EQ(d.verdict, "mount_stretch") << d.reason;
  const EffectFit& f = fit_of(d, EffectId::kMountStretch);
  EXPECT_TRUE(f.extended);
  EXPECT_NEAR(param(f, "shaped_share"), 0.5, 0.2);
  EXPECT_NEAR(param(f, "exponent"), 1.0, 0.5);
}

// A relaxed wrist that stiffens towards its limits (physics/relaxed_wrist.h, Riener & Edrich's double exponential)
// holds each muscle's range of motion back and bends the trajectories near the limits. The whole catalogue names it
// passive_wrist and recovers the stiffening, not a stiffer linear wrist.
TEST_F(DiagnosisTest, RelaxedWristStiffeningTowardsItsLimitsIsPassiveWrist) {
  SOFTWRIST_SKIP_END_TO_END_UNDER_SANITIZERS();
  sim::DeviceDescription real = paper_device();
  real.wrist.limit_stiffening.torque = 2.0;
  const Diagnosis d = run({.device = real}, paper_device());
  ASSERT_EQ(d.verdict, "passive_wrist") << d.reason;
  const EffectFit& f = fit_of(d, EffectId::kPassiveWrist);
  EXPECT_NEAR(param(f, "limit_stiffening_nm"), 2.0, 0.3);
  EXPECT_NEAR(param(f, "stiffness_scale"), 1.0, 0.15);
}

// A relaxed wrist whose stiffness differs between the axes and towards either side of each (anisotropic passive
// stiffness, Formica et al. 2012): flexion/extension 1.5 times the nominal's with a = -0.5 (softer towards flexion,
// stiffer towards extension), ulnar/radial 1.6 times that with a = -0.3. One scale of both axes fits each task with
// another compromise: the extensions are kept and recover the shape (the search is what is tested, without
// tolerances: within them the mounts and rest lengths take part of a stiffer wrist first, docs/diagnosis.md).
TEST_F(DiagnosisTest, RelaxedWristStifferOneWayThanTheOtherIsPassiveWristWithItsExtensions) {
  SOFTWRIST_SKIP_END_TO_END_UNDER_SANITIZERS();
  sim::DeviceDescription real = paper_device();
  real.wrist.stiffness_fe *= 1.5;
  real.wrist.stiffness_ur *= 1.5 * 1.6;
  real.wrist.stiffness_asymmetry_fe = -0.5;
  real.wrist.stiffness_asymmetry_ur = -0.3;
  write_synthetic_data({.device = real}, {.trajectory_s = 12.0}, dir_ / "real");
  const Diagnosis d =
      diagnose(load_real_data(dir_ / "real"), paper_device(), engine_,
               {.effects = {EffectId::kPassiveWrist}, .bootstrap = 100, .tolerances = Tolerances::none()});
  ASSERT_EQ(d.verdict, "passive_wrist") << d.reason;
  const EffectFit& f = fit_of(d, EffectId::kPassiveWrist);
  EXPECT_TRUE(f.extended);
  EXPECT_GT(f.shrink_fraction, 0.9);
  EXPECT_NEAR(param(f, "stiffness_scale"), 1.5, 0.15);
  EXPECT_NEAR(param(f, "deviation_stiffness_ratio"), 1.6, 0.2);
  EXPECT_NEAR(param(f, "asymmetry_fe"), -0.5, 0.1);
  EXPECT_NEAR(param(f, "asymmetry_ur"), -0.3, 0.1);
}

// An effect's extensions are searched whatever its base form closed (extend_fit): a relaxed wrist softer towards
// flexion and stiffer towards extension (a_fe = -0.5, a_ur = +0.4), each axis's mean stiffness the nominal's, fitted by
// the base form (one scale) and then credited with nothing, as on the independent device's direction_dependent at level
// 0.8 (within the tolerances the base form cut the held-out error 4 % and the training error 9.5 %: below min_gain,
// its extensions were not searched and the data set read `unexplained`; docs/diagnosis.md). They are kept and recover
// the shape.
TEST_F(DiagnosisTest, ExtensionsAreSearchedWhereTheBaseFormClosesNothing) {
  SOFTWRIST_SKIP_END_TO_END_UNDER_SANITIZERS();
  sim::DeviceDescription real = paper_device();
  real.wrist.stiffness_asymmetry_fe = -0.5;
  real.wrist.stiffness_asymmetry_ur = 0.4;
  write_synthetic_data({.device = real}, {.trajectory_s = 12.0}, dir_ / "real");
  const DiagnosisOptions options{
      .effects = {EffectId::kPassiveWrist}, .bootstrap = 100, .tolerances = Tolerances::none()};
  Diagnosis d = diagnose(load_real_data(dir_ / "real"), paper_device(), engine_, options);
  GapProblem problem(d.prepared, engine_);
  const ModelVariant nominal{.device = paper_device()};
  const Predictions training = problem.evaluate(nominal, true), full = problem.evaluate(nominal, false);
  const BaseModel base{.variant = nominal, .training = training, .full = full};
  EffectFit fit = fit_effect(problem, EffectId::kPassiveWrist, base, paper_device(), options, 7);
  ASSERT_TRUE(fit.applicable);
  // Credited with nothing: neither of the held-out error nor of the training error (extend_fit reads neither figure).
  fit.shrink_fraction = 0.0;
  fit.train_error_before = fit.train_error_after;
  const double base_form_heldout = fit.heldout_error_after;
  const auto base_form_params = fit.params;
  ASSERT_TRUE(extend_fit(problem, fit, base, paper_device(), options, 7));
  EXPECT_LT(fit.heldout_error_after, base_form_heldout);
  EXPECT_TRUE(fit.extended);
  // The base form it replaced is kept, for the rules that read a parameter in the catalogue's form.
  ASSERT_TRUE(fit.base_form.has_value());
  EXPECT_EQ(fit.base_form->params, base_form_params);
  EXPECT_EQ(fit.base_form->shrink_fraction, 0.0);
  EXPECT_DOUBLE_EQ(problem.heldout_error(fit.base_form->heldout_after_sums), base_form_heldout);
  EXPECT_NE(fit.params, base_form_params);
  EXPECT_GT(fit.shrink_fraction, 0.8);
  EXPECT_NEAR(param(fit, "asymmetry_fe"), -0.5, 0.1);
  EXPECT_NEAR(param(fit, "asymmetry_ur"), 0.4, 0.1);
}

// Two effects at once (issue 20: the verdict names the larger and reports the second): fabric 5 % wider than the
// paper's and a relaxed wrist that stiffens towards its limits. Whether one alone closes 60 % of the gap or only the
// two together do, the verdict and also_effects name exactly these two. (Ranked beyond the tolerances, the second is
// not found here: docs/diagnosis.md, Known limits.)
TEST_F(DiagnosisTest, TwoEffectsAtOnceAreBothNamed) {
  SOFTWRIST_SKIP_END_TO_END_UNDER_SANITIZERS();
  sim::DeviceDescription real = paper_device();
  std::vector<physics::FpamTableRow> rows = real.fpam.rows();
  for (auto& row : rows) row.radius *= 1.05;
  real.fpam = physics::FpamParameters::Table(rows, real.fpam.fabric());
  real.wrist.limit_stiffening.torque = 2.0;
  const Diagnosis d = run({.device = real}, paper_device());
  std::set<std::string> named(d.also_effects.begin(), d.also_effects.end());
  named.insert(d.verdict);
  if (d.also_effects.empty() && d.combination.size() >= 2) named.insert(d.combination[1].name);
  EXPECT_EQ(named, (std::set<std::string>{"fpam_params", "passive_wrist"})) << d.reason;
}

TEST_F(DiagnosisTest, ImportChecksUnitsAndCells) {
  const auto write = [&](const std::string& name, const std::string& text) {
    std::ofstream(dir_ / name) << text;
    return dir_ / name;
  };
  const auto message = [&](const fs::path& csv, const std::string& kind) {
    try {
      import_csv(csv, dir_ / "out", {.kind = kind});
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message(write("a.csv", "angle,pressure_kpa,torque_nm\n0,34,1\n"), "torque-sweep")
                .find("column 'angle' states no unit"),
            std::string::npos);
  EXPECT_NE(message(write("b.csv", "angle_deg,pressure_psi,torque_nm\n0,5,1\n"), "torque-sweep")
                .find("unit 'psi' is not read"),
            std::string::npos);
  EXPECT_NE(message(write("c.csv", "angle_deg,pressure_kpa,torque_nm\n0,34,1\n# a note\n10,nan,2\n"), "torque-sweep")
                .find("c.csv:4: pressure_kpa"),
            std::string::npos);
  EXPECT_NE(
      message(write("d.csv", "pressure_kpa,contraction,force_n,direction\n34,0.1,20,up\n"), "tensile").find("'up'"),
      std::string::npos);
  EXPECT_NE(message(write("e.csv", "x\n1\n"), "speed").find("--kind"), std::string::npos);
  EXPECT_FALSE(fs::exists(dir_ / "out/trials.csv"));

  const auto result =
      import_csv(write("ok.csv", "angle_deg,pressure_kpa,torque_nm,repetition\n0,34,1.5,0\n10,34,1.2,1\n"),
                 dir_ / "out", {.kind = "torque-sweep"});
  EXPECT_EQ(result.rows, 2u);
  const auto trials = read_trials(dir_ / "out/trials.json", "out");
  ASSERT_EQ(trials.size(), 1u);
  ASSERT_EQ(trials[0].sweep.size(), 2u);
  EXPECT_NEAR(trials[0].sweep[1].angle, 10.0 * M_PI / 180.0, 1e-12);
  EXPECT_DOUBLE_EQ(trials[0].sweep[1].pressure, 34e3);
  EXPECT_EQ(trials[0].sweep[1].repetition, 1);
  EXPECT_THROW(import_csv(dir_ / "ok.csv", dir_ / "out", {.kind = "torque-sweep"}), std::runtime_error);  // occupied

  // Measured pressures come with a trajectory as all four columns or none.
  const std::string trajectory_header =
      "t_s,cmd_flexor_kpa,cmd_extensor_kpa,cmd_ulnar_kpa,cmd_radial_kpa,angle_fe_deg,angle_ur_deg";
  std::string rows;
  for (int i = 0; i < 10; ++i) rows += fmt::format("{},10,0,0,0,1,0,9.5,0.1,-0.2,0\n", 0.014 * i);
  import_csv(write("traj.csv", trajectory_header + ",p_flexor_kpa,p_extensor_kpa,p_ulnar_kpa,p_radial_kpa\n" + rows),
             dir_ / "traj", {.kind = "trajectory"});
  const auto trajectory = read_trials(dir_ / "traj/trials.json", "traj").at(0).trajectory;
  ASSERT_TRUE(trajectory.at(3).measured_kpa.has_value());
  EXPECT_DOUBLE_EQ((*trajectory[3].measured_kpa)[0], 9.5);
  EXPECT_DOUBLE_EQ((*trajectory[3].measured_kpa)[2], -0.2);  // a sensor's zero may read below zero
  std::string two_rows;
  for (int i = 0; i < 10; ++i) two_rows += fmt::format("{},10,0,0,0,1,0,9.5,0.1\n", 0.014 * i);
  std::string partial = "no error";
  try {
    import_csv(write("partial.csv", trajectory_header + ",p_flexor_kpa,p_ulnar_kpa\n" + two_rows), dir_ / "partial",
               {.kind = "trajectory"});
  } catch (const std::runtime_error& e) {
    partial = e.what();
  }
  EXPECT_NE(partial.find("2 of the four measured-pressure columns"), std::string::npos) << partial;
  EXPECT_NE(partial.find("partial.csv"), std::string::npos) << partial;

  // --hand-supported reaches the replay of any kind, here a range of motion.
  import_csv(write("rom.csv", "muscle,pressure_kpa,limit_deg\nflexor,137,30\n"), dir_ / "rom",
             {.kind = "rom", .hand_supported = true});
  EXPECT_EQ(read_trials(dir_ / "rom/trials.json", "rom").at(0).conventions.posture, Posture::kHandSupported);

  // The conventions a user states reach the trial; a bad one is refused naming its field, and nothing is written.
  import_csv(write("rom2.csv", "muscle,pressure_kpa,limit_deg\nflexor,137,30\n"), dir_ / "rom2",
             {.kind = "rom",
              .posture = "gravity_fe",
              .angles_zeroed = true,
              .angle_resolution_deg = 0.0625,
              .placement = (fs::path(SOFTWRIST_SOURCE_DIR) / "models/rom_device.json").string()});
  const Conventions c = read_trials(dir_ / "rom2/trials.json", "rom2").at(0).conventions;
  EXPECT_EQ(c.posture, Posture::kGravityFe);
  EXPECT_TRUE(c.angles_zeroed_at_start);
  EXPECT_NEAR(c.angle_resolution, 0.0625 * M_PI / 180.0, 1e-15);
  EXPECT_EQ(c.placement, fs::path(SOFTWRIST_SOURCE_DIR) / "models/rom_device.json");
  const auto refused = [&](ImportOptions options) {
    options.kind = options.kind.empty() ? "rom" : options.kind;
    try {
      import_csv(dir_ / (options.kind == "rom" ? "rom2.csv" : "ok.csv"), dir_ / "refused", options);
    } catch (const std::runtime_error& e) {
      EXPECT_FALSE(fs::exists(dir_ / "refused/trials.csv"));
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(refused({.posture = "upside_down"}).find("config.posture: 'upside_down'"), std::string::npos);
  EXPECT_NE(refused({.torque_includes = "muscle"}).find("--torque-includes: applies to torque-sweep, not rom"),
            std::string::npos);
  EXPECT_NE(refused({.kind = "torque-sweep", .torque_includes = "muscle+gravity"})
                .find("config.torque_includes: 'muscle+gravity'"),
            std::string::npos);
  EXPECT_NE(refused({.placement = (dir_ / "missing.json").string()}).find("missing.json"), std::string::npos);
  EXPECT_NE(refused({.angle_resolution_deg = -1}).find("config.angle_resolution_deg: must be >= 0"), std::string::npos);
}

}  // namespace
}  // namespace softwrist::diagnosis
