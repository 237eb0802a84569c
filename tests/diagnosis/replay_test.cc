// Replaying a trajectory's logged commands (diagnosis/replay.h): a regulator dead time reaches the regulators within
// a simulation step, and the replay is continuous in it; on the step's grid it is the row in force, as a simulation
// that switches the command at the step does. Where measured pressures drive the muscles (PressureSource), the
// regulators replayed alone give MuJoCo's pressures, and the angles are those of the commands' replay when the
// measured pressures are the model's own, from the start the log's first measured pressures show (a log that begins
// while the regulators still move). An effect acts on (acts_on) exactly the trials whose replay it changes.

#include "diagnosis/replay.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "diagnosis/conventions.h"
#include "diagnosis/effects.h"
#include "physics/pressure_regulator.h"
#include "physics/units.h"
#include "sim/device.h"
#include "sim/model_builder.h"
#include "sim/wrist_sim.h"

namespace softwrist::diagnosis {
namespace {

constexpr double kRow = 0.014;              // [s] the paper's control period
constexpr double kStep = 0.2;               // [s] the flexor's command steps to 100 kPa here
constexpr double kEnd = 0.5;                // [s]
constexpr std::size_t kFlexorPressure = 0;  // the pressures' trial: channel 2 + muscle, muscle-major

class ReplayDeadTime : public ::testing::Test {
 protected:
  ReplayDeadTime() {
    trial_.kind = TrialKind::kTrajectory;
    trial_.name = trial_.file = "steps";
    for (int i = 0; i * kRow <= kEnd + 1e-9; ++i) {
      TrajectorySample s{.t = i * kRow};
      if (s.t >= kStep) s.command_kpa[0] = 100.0;
      s.measured_kpa = control::Pressures{};
      trial_.trajectory.push_back(s);
    }
    data_.trials.push_back(trial_);
    prepared_ = prepare(data_, engine_, ModelVariant{.device = sim::paper_device()});
  }

  // The flexor's replayed pressure [kPa] at each row, with the commands `dead_time` late.
  std::vector<double> flexor_pressure(double dead_time) {
    const PreparedTrial& pressures = prepared_.at(1);
    EXPECT_TRUE(pressures.pressures);
    const std::vector<double> all = engine_.predict(
        pressures, ModelVariant{.device = sim::paper_device(), .regulator_dead_time = dead_time}, false);
    const std::size_t n = trial_.trajectory.size();
    return {all.begin() + static_cast<long>(kFlexorPressure * n),
            all.begin() + static_cast<long>((kFlexorPressure + 1) * n)};
  }

  Trial trial_;
  RealData data_;
  ReplayEngine engine_{sim::PluginSet::Default(), {}, PressureSource::kCommands};
  std::vector<PreparedTrial> prepared_;
};

TEST_F(ReplayDeadTime, ADeadTimeWithinAStepMovesThePressuresContinuously) {
  // 10.5 ms: the step to 100 kPa reaches the regulators half way through a 1 ms step. Applied at the next step, the
  // replay would be the 11 ms one; it is the mean of the 10 and 11 ms replays instead.
  const std::vector<double> early = flexor_pressure(0.010), half = flexor_pressure(0.0105),
                            late = flexor_pressure(0.011);
  int rising = 0;
  for (std::size_t i = 0; i < half.size(); ++i) {
    if (early[i] - late[i] < 0.05) continue;  // before the step, or settled
    ++rising;
    // The regulator is linear and stepped exactly, and the half step's mean command is the mean of the other two
    // replays' commands in that step: the mean of their pressures, to rounding.
    EXPECT_NEAR(half[i], 0.5 * (early[i] + late[i]), 1e-9) << "row " << i;
  }
  EXPECT_GE(rising, 10);
}

TEST_F(ReplayDeadTime, OnTheStepsGridItIsTheRowInForce) {
  // 4 ms, rows every 14 ms: every change falls on a step's start. The same commands switched at the step in a
  // simulation of the same model give the same pressures to the last bit.
  const std::vector<double> replayed = flexor_pressure(0.004);
  sim::ModelOptions options;
  options.anatomy = false;
  options.gravity = 0.0;
  const sim::Model model =
      sim::Model::FromXml(sim::build_model_xml(sim::paper_device(), options), sim::PluginSet::Default(), "steps");
  sim::WristSim wrist(model);
  wrist.reset();
  const double dt = model->opt.timestep;
  double first_on = 0.0;  // the first row that commands 100 kPa
  for (const TrajectorySample& s : trial_.trajectory) {
    if (s.command_kpa[0] > 0.0 && first_on == 0.0) first_on = s.t;
  }
  std::vector<double> direct;
  for (int k = 0; direct.size() < trial_.trajectory.size(); ++k) {
    const double t = k * dt;
    if (std::abs(t - trial_.trajectory[direct.size()].t) < 1e-9) {
      direct.push_back(wrist.regulated_pressure_kpa(sim::kFlexor));
    }
    wrist.command_pressures_kpa({t >= first_on + 0.004 - 1e-9 ? 100.0 : 0.0, 0.0, 0.0, 0.0});
    wrist.run(dt);
  }
  ASSERT_EQ(replayed.size(), direct.size());
  for (std::size_t i = 0; i < direct.size(); ++i) EXPECT_EQ(replayed[i], direct[i]) << "row " << i;
}

TEST_F(ReplayDeadTime, ZeroedAnglesTakeTheirOriginFromTheTrainingRowsAlone) {
  // A real trial need not start at rest, so zeroed angles read 0 at an origin the model cannot know: the replay fits
  // it per trial and angle as the mean residual of the training rows. The whole log shifted by a constant shifts the
  // prediction by it, in that angle only; the held-out half's readings do not move the prediction at all.
  RealData data = data_;
  data.trials[0].conventions.angles_zeroed_at_start = true;
  const ModelVariant nominal{.device = sim::paper_device()};
  const std::vector<PreparedTrial> prepared = prepare(data, engine_, nominal);
  PreparedTrial angles = prepared.at(0);
  ASSERT_FALSE(angles.pressures);
  const std::vector<double> before = engine_.predict(angles, nominal, false);
  PreparedTrial shifted = angles, heldout_moved = angles;
  int training_fe = 0, heldout = 0;
  for (std::size_t i = 0; i < angles.points.size(); ++i) {
    if (angles.points[i].channel == 0) shifted.points[i].measured += 1.5;
    if (angles.points[i].heldout) heldout_moved.points[i].measured += 5.0, ++heldout;
    if (angles.points[i].channel == 0 && !angles.points[i].heldout) ++training_fe;
  }
  ASSERT_GT(training_fe, 5);
  ASSERT_GT(heldout, 5);
  const std::vector<double> after_shift = engine_.predict(shifted, nominal, false);
  const std::vector<double> after_heldout = engine_.predict(heldout_moved, nominal, false);
  double mean_training_residual_fe = 0.0;
  for (std::size_t i = 0; i < angles.points.size(); ++i) {
    const double expected_shift = angles.points[i].channel == 0 ? 1.5 : 0.0;
    EXPECT_NEAR(after_shift[i] - before[i], expected_shift, 1e-9) << "point " << i;
    EXPECT_NEAR(after_heldout[i], before[i], 1e-12) << "point " << i;
    if (angles.points[i].channel == 0 && !angles.points[i].heldout)
      mean_training_residual_fe += (angles.points[i].measured - before[i]) / training_fe;
  }
  EXPECT_NEAR(mean_training_residual_fe, 0.0, 1e-9);
}

// A repeated task's repetitions alternate whole between the training and the held-out part (split_by_repetition), so
// that both parts reach every state the task does; a trial of no repeated task keeps its time split (the first half
// trains). A repetition held out whole takes its zeroed angles' origin from its own rows, and has nothing to replay
// for the training part.
TEST_F(ReplayDeadTime, RepetitionsOfATaskAlternateWholeBetweenTrainingAndHeldOut) {
  RealData data = data_;
  data.trials[0].conventions.angles_zeroed_at_start = true;
  Trial again = data.trials[0];
  again.name = again.file = "steps again";
  data.trials.push_back(again);
  const ModelVariant nominal{.device = sim::paper_device()};
  const std::vector<PreparedTrial> prepared = prepare(data, engine_, nominal);
  ASSERT_EQ(prepared.size(), 4u);  // each repetition's angles and pressures
  for (std::size_t t = 0; t < 4; ++t) {
    const bool held_out = prepared[t].trial->name == "steps again";
    for (const Point& point : prepared[t].points) ASSERT_EQ(point.heldout, held_out) << prepared[t].name;
  }
  PreparedTrial second = prepared.at(2);
  ASSERT_FALSE(second.pressures);
  for (double v : engine_.predict(second, nominal, true)) EXPECT_TRUE(std::isnan(v));
  const std::vector<double> before = engine_.predict(second, nominal, false);
  for (Point& point : second.points) point.measured += 1.5;
  const std::vector<double> after = engine_.predict(second, nominal, false);
  for (std::size_t i = 0; i < before.size(); ++i) EXPECT_NEAR(after[i] - before[i], 1.5, 1e-9) << "point " << i;

  const std::vector<PreparedTrial> alone = prepare(data_, engine_, nominal);
  const auto held_out = std::count_if(alone.at(0).points.begin(), alone.at(0).points.end(),
                                      [](const Point& point) { return point.heldout; });
  EXPECT_GT(held_out, 0);
  EXPECT_LT(held_out, static_cast<long>(alone.at(0).points.size()));
}

TEST_F(ReplayDeadTime, ReplaysAreCountedAndCachedOnesAreNot) {
  const ReplayStats before = engine_.stats();
  flexor_pressure(0.02);
  flexor_pressure(0.02);  // the same variant: from the cache
  flexor_pressure(0.03);
  const ReplayStats after = engine_.stats();
  EXPECT_EQ(after.trajectories - before.trajectories, 2);
  EXPECT_EQ(after.cache_hits - before.cache_hits, 1);
  EXPECT_NEAR(after.trajectory_sim_s - before.trajectory_sim_s, 2 * trial_.trajectory.back().t, 1e-9);
  EXPECT_GT(after.trajectory_s, before.trajectory_s);
  EXPECT_EQ(after.settles, 0);  // no range of motion here
}

// A fit differences coarse replays (Fidelity::kCoarse, ReplaySteps::coarse) and compares fine ones: a coarse replay is
// one of its own (cached apart from the fine one), and the change a parameter makes to the angles is nearly the
// same at either step, while the angles themselves differ more (measured: mounts 20 % stiffer move the angles by up
// to 0.91 deg; the 5 ms replay's angles are up to 0.41 deg from the 1 ms one's through the flexor's step, its change
// within 0.009 deg of theirs).
TEST_F(ReplayDeadTime, CoarseReplaysChangeWithAParameterAsFineOnesDo) {
  const ModelVariant nominal{.device = sim::paper_device()};
  ModelVariant stiffer = nominal;
  std::vector<double> k = fit_start(EffectId::kMountStretch, nominal.device);
  k[0] *= 1.2;
  apply_effect(EffectId::kMountStretch, k, stiffer);
  const PreparedTrial& angles = prepared_.at(0);
  const long before = engine_.stats().trajectories;
  const auto fine = engine_.predict(angles, nominal, false),
             coarse = engine_.predict(angles, nominal, false, Fidelity::kCoarse);
  const auto fine_moved = engine_.predict(angles, stiffer, false);
  const auto coarse_moved = engine_.predict(angles, stiffer, false, Fidelity::kCoarse);
  EXPECT_EQ(engine_.stats().trajectories - before, 4);
  double change = 0.0, step_error = 0.0, change_error = 0.0;
  for (std::size_t i = 0; i < fine.size(); ++i) {
    change = std::max(change, std::abs(fine_moved[i] - fine[i]));
    step_error = std::max(step_error, std::abs(coarse[i] - fine[i]));
    change_error = std::max(change_error, std::abs((coarse_moved[i] - coarse[i]) - (fine_moved[i] - fine[i])));
  }
  EXPECT_GT(change, 0.05);  // [deg] the stiffer mounts move the wrist
  EXPECT_LT(change_error, 0.1 * change) << "step error " << step_error;
  EXPECT_LT(change_error, 0.5 * step_error);  // the step's error largely cancels in the difference
}

// A paper device whose regulator vents slower than it fills, or responds in second order.
ModelVariant regulator_variant(bool second_order, double dead_time) {
  ModelVariant variant{.device = sim::paper_device(), .regulator_dead_time = dead_time};
  variant.device.regulator.vent_time_constant = 0.25;
  if (second_order) variant.device.regulator.second_order_time = 0.06;
  return variant;
}

TEST_F(ReplayDeadTime, TheRegulatorsAloneGiveTheSimulationsPressures) {
  // Rows on and off the step's grid (4 ms, 10.5 ms of dead time), filling and venting, first and second order, from
  // rest or (angles zeroed at the start) settled under the first command: the regulators replayed without MuJoCo
  // integrate as the plugin does in it. The measured pressures are the simulation's own, so that the start fitted to
  // them (ReplayEngine::measured_regulator_start) is the model's.
  for (const bool zeroed : {false, true}) {
    RealData data = data_;
    data.trials[0].conventions.angles_zeroed_at_start = zeroed;
    if (zeroed) {
      for (auto& s : data.trials[0].trajectory) s.command_kpa[1] = s.t < kStep ? 40.0 : 0.0;  // the extensor vents
    }
    const ModelVariant nominal{.device = sim::paper_device()};
    const std::vector<PreparedTrial> simulated_trials = prepare(data, engine_, nominal);
    for (const bool second_order : {false, true}) {
      for (const double dead_time : {0.004, 0.0105}) {
        const ModelVariant variant = regulator_variant(second_order, dead_time);
        const std::vector<double> simulated = engine_.predict(simulated_trials.at(1), variant, false);
        RealData logged = data;
        const std::size_t n = logged.trials[0].trajectory.size();
        for (std::size_t i = 0; i < n; ++i) {
          for (std::size_t m = 0; m < 4; ++m) (*logged.trials[0].trajectory[i].measured_kpa)[m] = simulated[m * n + i];
        }
        ReplayEngine measured(sim::PluginSet::Default());
        const std::vector<PreparedTrial> alone_trials = prepare(logged, measured, nominal);
        ASSERT_TRUE(alone_trials.at(0).angles_from_measured_pressures);
        ASSERT_TRUE(alone_trials.at(1).pressures);
        const long angle_replays = measured.stats().trajectories;  // preparing the angles' noise replays them
        const std::vector<double> alone = measured.predict(alone_trials.at(1), variant, false);
        EXPECT_EQ(measured.stats().trajectories, angle_replays);  // no MuJoCo replay for the pressures
        ASSERT_EQ(alone.size(), simulated.size());
        double largest = 0.0;
        for (double p : simulated) largest = std::max(largest, p);
        EXPECT_GT(largest, 50.0);
        for (std::size_t i = 0; i < alone.size(); ++i) {
          EXPECT_NEAR(alone[i], simulated[i], 1e-9) << "zeroed " << zeroed << ", second order " << second_order
                                                    << ", dead time " << dead_time << ", point " << i;
        }
      }
    }
  }
}

// A log that begins while the regulators still move (issue 20: the independent rig's trials begin 0.3-1 s after the
// first pressures were commanded, and a ringing regulator takes seconds to settle): muscles 0 and 1 start 12 kPa and 6
// kPa off the model's start (settled under the first command), moving, and muscle 0's command steps at 0.49 s. A row
// every 14 ms (the paper's loop) from first_row_s on; truth holds the regulators' own pressures at each row, the log's
// measured pressures those with the monitors' noise where noise is given.
struct LateStart {
  ModelVariant variant;
  Trial trial;
  std::vector<control::Pressures> truth;
};

LateStart late_start_log(bool second_order, double first_row_s, std::mt19937* noise) {
  constexpr double kDt = 0.001;  // [s] ReplaySteps::trajectory
  LateStart log{.variant = ModelVariant{.device = sim::paper_device()},
                .trial = Trial{.kind = TrialKind::kTrajectory, .name = "late start", .file = "late.csv"}};
  log.variant.device.regulator.time_constant = 0.08;
  if (second_order) log.variant.device.regulator.second_order_time = 0.15;  // damping ratio 0.27: it rings
  const physics::RegulatorResponse response = log.variant.device.regulator.response();
  log.trial.conventions.angles_zeroed_at_start = true;
  std::array<physics::RegulatedPressure, 4> state{};
  state[0] = {8.0, second_order ? 150.0 : 0.0};
  state[1] = {36.0, second_order ? -50.0 : 0.0};
  std::normal_distribution<double> monitor(0.0, 0.15);  // [kPa] the independent rig's monitors
  for (int k = 0; k <= 1500; ++k) {
    const double t = kDt * k;
    const control::Pressures command{t >= 0.49 ? 60.0 : 20.0, 30.0, 0.0, 0.0};
    if (k % 14 == 0 && t >= first_row_s - 1e-9) {
      control::Pressures truth{}, read{};
      for (std::size_t m = 0; m < 4; ++m) {
        truth[m] = state[m].pressure;
        // Read to the bridge's 0.1 kPa where noisy.
        read[m] = noise == nullptr ? truth[m] : std::round(10.0 * (truth[m] + monitor(*noise))) / 10.0;
      }
      log.trial.trajectory.push_back({.t = t, .command_kpa = command, .measured_kpa = read});
      log.truth.push_back(truth);
    }
    for (std::size_t m = 0; m < 4; ++m) {  // as the plugin steps them (ReplayEngine::replay_regulators)
      if (second_order) {
        state[m] = physics::regulator_step(response, state[m], command[m], kDt);
      } else {
        state[m].pressure += kDt * physics::pressure_rate(response, command[m], state[m].pressure);
      }
    }
  }
  return log;
}

// The regulators' pressures replayed at each row of the log's pressures trial, muscle-major.
std::vector<double> replay_pressures(const LateStart& log) {
  RealData data;
  data.trials.push_back(log.trial);
  ReplayEngine engine(sim::PluginSet::Default());
  const std::vector<PreparedTrial> prepared = prepare(data, engine, ModelVariant{.device = sim::paper_device()});
  EXPECT_TRUE(prepared.at(1).pressures);
  return engine.predict(prepared.at(1), log.variant, false);
}

// Fitted to the first measured pressures (ReplayEngine::measured_regulator_start), the state at the first row is the
// one the log began from, pressure and rate, and the replay is the log, first and second order, the rows after the
// fitted window too; so too where the log's first row comes 0.3 s after the replay's start (the state is moved at the
// first row, not at t = 0, where a start 12 kPa off would have decayed to 0.3 kPa).
TEST(ReplayRegulatorStart, ALogThatBeginsWhileTheRegulatorsStillMoveIsReplayedFromItsFirstMeasuredPressures) {
  for (const double first_row_s : {0.0, 0.3}) {
    for (const bool second_order : {false, true}) {
      const LateStart log = late_start_log(second_order, first_row_s, nullptr);
      ASSERT_GE(log.trial.trajectory.front().t, first_row_s);
      const std::vector<double> replayed = replay_pressures(log);
      const std::size_t n = log.truth.size();
      ASSERT_EQ(replayed.size(), 4 * n);
      for (std::size_t m = 0; m < 4; ++m) {
        for (std::size_t i = 0; i < n; ++i) {
          EXPECT_NEAR(replayed[m * n + i], log.truth[i][m], 1e-6) << "first row " << first_row_s << " s, second order "
                                                                  << second_order << ", muscle " << m << ", row " << i;
        }
      }
    }
  }
}

// The same logs read by monitors with 0.15 kPa of noise to 0.1 kPa (the independent rig's): the start is fitted to
// 18 noisy rows, and the replay follows the regulators' own pressures to a fraction of the noise over the whole log
// (rms over 20 logs), where the model's settled start misses the first rows by up to 12 kPa.
TEST(ReplayRegulatorStart, MonitorNoiseMovesTheFittedStartByAFractionOfTheNoise) {
  std::mt19937 noise(20261202);
  for (const bool second_order : {false, true}) {
    double squares = 0.0, first_row = 0.0;
    std::size_t count = 0;
    for (int log_index = 0; log_index < 20; ++log_index) {
      const LateStart log = late_start_log(second_order, 0.0, &noise);
      const std::vector<double> replayed = replay_pressures(log);
      const std::size_t n = log.truth.size();
      ASSERT_EQ(replayed.size(), 4 * n);
      for (std::size_t m = 0; m < 4; ++m) {
        for (std::size_t i = 0; i < n; ++i) {
          const double error = replayed[m * n + i] - log.truth[i][m];
          squares += error * error;
          ++count;
          if (i == 0) first_row = std::max(first_row, std::abs(error));
        }
      }
    }
    const double rms = std::sqrt(squares / static_cast<double>(count));
    EXPECT_LT(rms, 0.05) << "second order " << second_order;       // [kPa] a third of the monitors' noise
    EXPECT_LT(first_row, 0.3) << "second order " << second_order;  // [kPa] two noise units at worst
  }
}

// The measured pressures are compared with the regulators' alone: every effect but the regulators' leaves them as
// they are, and so is not scored on them (acts_on), whether the pressures are replayed alone or in MuJoCo.
TEST_F(ReplayDeadTime, OnlyTheRegulatorsEffectActsOnTheMeasuredPressures) {
  const ModelVariant nominal{.device = sim::paper_device()};
  ReplayEngine measured(sim::PluginSet::Default());
  const std::vector<PreparedTrial> alone_trials = prepare(data_, measured, nominal);
  for (const EffectSpec& spec : effect_catalogue()) {
    // Each parameter a quarter of the way from the nominal's start to the top of its range: the effect switched on.
    std::vector<double> values = fit_start(spec.id, nominal.device);
    for (std::size_t i = 0; i < values.size(); ++i) {
      const ParameterSpec& p = spec.parameters[i];
      values[i] = p.from_unit(p.to_unit(values[i]) + 0.25 * (1.0 - p.to_unit(values[i])));
    }
    ModelVariant variant = nominal;
    apply_effect(spec.id, values, variant);
    for (const auto& [engine, trials] :
         {std::pair<ReplayEngine*, const std::vector<PreparedTrial>*>{&engine_, &prepared_},
          {&measured, &alone_trials}}) {
      const PreparedTrial& pressures = trials->at(1);
      ASSERT_TRUE(pressures.pressures);
      const bool changed = engine->predict(pressures, variant, false) != engine->predict(pressures, nominal, false);
      EXPECT_EQ(acts_on(spec, pressures), spec.id == EffectId::kRegulatorLag) << spec.name;
      EXPECT_EQ(changed, spec.id == EffectId::kRegulatorLag) << spec.name;
    }
  }
}

TEST_F(ReplayDeadTime, MeasuredPressuresThatAreTheModelsOwnGiveTheCommandsAngles) {
  // The model's own regulated pressures logged every step (1 ms): driven by them, the muscles see what the
  // commands' replay gave them, so the angles agree; a regulator effect then moves neither the angles nor the
  // replay count (a fit of it reuses the angles' replay), while the mount's stiffness moves the angles.
  Trial trial = trial_;
  trial.name = trial.file = "fine";
  trial.trajectory.clear();
  for (int i = 0; i * 0.001 <= kEnd + 1e-9; ++i) {
    TrajectorySample s{.t = i * 0.001};
    if (s.t >= kStep) s.command_kpa[0] = 100.0;
    if (s.t >= kStep + 0.15) s.command_kpa[2] = 60.0;
    s.measured_kpa = control::Pressures{};
    trial.trajectory.push_back(s);
  }
  RealData data;
  data.trials.push_back(trial);
  const ModelVariant nominal{.device = sim::paper_device()};
  const std::vector<PreparedTrial> from_commands = prepare(data, engine_, nominal);
  const std::vector<double> pressures = engine_.predict(from_commands.at(1), nominal, false);
  const std::size_t n = trial.trajectory.size();
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t m = 0; m < 4; ++m) (*data.trials[0].trajectory[i].measured_kpa)[m] = pressures[m * n + i];
  }
  const std::vector<double> commanded = engine_.predict(from_commands.at(0), nominal, false);
  ReplayEngine measured(sim::PluginSet::Default());
  const std::vector<PreparedTrial> from_measured = prepare(data, measured, nominal);
  const std::vector<double> driven = measured.predict(from_measured.at(0), nominal, false);
  ASSERT_EQ(driven.size(), commanded.size());
  double moved = 0.0;
  for (std::size_t i = 0; i < driven.size(); ++i) {
    EXPECT_NEAR(driven[i], commanded[i], 1e-9) << "point " << i;
    moved = std::max(moved, std::abs(commanded[i]));
  }
  EXPECT_GT(moved, 5.0);  // [deg] the flexor and the ulnar muscle moved the wrist

  const EffectSpec& regulator = effect_spec(EffectId::kRegulatorLag);
  EXPECT_FALSE(acts_on(regulator, from_measured.at(0)));
  EXPECT_TRUE(acts_on(regulator, from_measured.at(1)));
  EXPECT_TRUE(acts_on(regulator, from_commands.at(0)));
  EXPECT_TRUE(acts_on(effect_spec(EffectId::kMountStretch), from_measured.at(0)));
  const long replays = measured.stats().trajectories;
  EXPECT_EQ(measured.predict(from_measured.at(0), regulator_variant(true, 0.03), false), driven);
  EXPECT_EQ(measured.stats().trajectories, replays);
  ModelVariant stretched = nominal;
  apply_effect(EffectId::kMountStretch, std::vector<double>{3.0, 2.0, 0.0, 1.0}, stretched);  // K_s, the paper's law
  const std::vector<double> stiffer = measured.predict(from_measured.at(0), stretched, false);
  EXPECT_GT(std::abs(stiffer.back() - driven.back()), 0.1);  // [deg]
}

// A torque sweep whose order alternates between repetitions (issue 20: a rig's sweep goes up the angles, then down):
// every held angle is reached from a different side in each, so no condition repeats from one side and the pooled
// spread of repeats is not to be had. The measurements are the nominal's torques 20 % weaker (a misfit that changes
// from one pressure to the next) with 5 mN m of noise: the successive differences hold the misfit, the spread between
// the two sides does not.
class AlternatingSweepNoise : public ::testing::Test {
 protected:
  static constexpr double kNoise = 0.005;  // [N m]

  // The sweep: 5 held angles x 5 pressures, up the angles in repetition 1 and down them in repetition 2, each
  // measurement `scale` times the nominal's torque, `side_offset` [N m] times the pressure over the highest added
  // where the angle was reached going down (a hysteresis, which grows with the muscle's force), and noise.
  // `setting_offset` [N m]: the standard deviation of an offset each held angle's readings share in a repetition (the
  // hand's seat, the relaxed wrist's tone; setting_scatter.h).
  PreparedTrial prepared_sweep(double scale, double side_offset, bool baseline_subtracted = false,
                               double setting_offset = 0.0) {
    Trial trial{.kind = TrialKind::kTorqueSweep, .name = "sweep", .file = "sweep.csv"};
    trial.conventions.torque.baseline_subtracted = baseline_subtracted;
    for (const int repetition : {1, 2}) {
      for (int a = 0; a < 5; ++a) {
        const int held = repetition == 1 ? a : 4 - a;
        for (int p = 0; p < 5; ++p) {
          trial.sweep.push_back({.angle = units::deg_to_rad(-40.0 + 20.0 * held),
                                 .pressure = units::kpa_to_pa(30.0 * p),
                                 .repetition = repetition,
                                 .motion = repetition == 1 ? 1 : -1});
        }
      }
    }
    data_.trials = {trial};
    const ModelVariant nominal{.device = sim::paper_device()};
    const std::vector<double> torque = engine_.predict(prepare(data_, engine_, nominal).at(0), nominal, false);
    std::mt19937_64 rng(11);
    std::normal_distribution<double> noise(0.0, kNoise), offset(0.0, setting_offset);
    double shared = 0.0;
    for (std::size_t i = 0; i < torque.size(); ++i) {
      SweepPoint& s = data_.trials[0].sweep[i];
      if (i % 5 == 0) shared = setting_offset > 0.0 ? offset(rng) : 0.0;  // five pressures per setting
      s.torque = scale * torque[i] + (s.motion < 0 ? side_offset * s.pressure / units::kpa_to_pa(120.0) : 0.0) +
                 noise(rng) + shared;
      if (baseline_subtracted && s.pressure == 0.0) s.torque = 0.0;  // the 0 kPa reading less itself
    }
    return prepare(data_, engine_, nominal).at(0);
  }

  RealData data_;  // the prepared trial points at its trial
  ReplayEngine engine_{sim::PluginSet::Default()};
};

TEST_F(AlternatingSweepNoise, TheSpreadBetweenTheSidesIsTheNoiseWhereTheMisfitChangesFromPointToPoint) {
  const PreparedTrial p = prepared_sweep(0.8, 0.0);
  EXPECT_NEAR(p.noise, kNoise, 0.35 * kNoise) << p.noise_source;
  EXPECT_NE(p.noise_source.find("either side"), std::string::npos) << p.noise_source;
  // Each held angle: 10 readings less 5 conditions and 2 settings' offsets (setting_scatter.h), plus 1.
  EXPECT_EQ(p.noise_dof, 20);
}

// A reading less the same angle's at 0 kPa is exactly 0 there, in the log and the model: those conditions hold no
// noise and count no degree of freedom (each held angle: 8 readings less 4 conditions and 2 settings, plus 1).
TEST_F(AlternatingSweepNoise, ReadingsDefinedAsZeroCountNoDegreeOfFreedom) {
  const PreparedTrial p = prepared_sweep(0.8, 0.0, true);
  EXPECT_EQ(p.noise_dof, 15);
  EXPECT_NEAR(p.noise, kNoise, 0.35 * kNoise) << p.noise_source;
}

// An offset each setting's readings share, ten times the sensor's noise: the readings' noise is still the sensor's,
// and the offset is the setting scatter (estimated from ten settings, taken at the upper end of its 75 % interval).
TEST_F(AlternatingSweepNoise, ASettingsSharedOffsetIsNotTheReadingsNoise) {
  const PreparedTrial p = prepared_sweep(0.8, 0.0, false, 10.0 * kNoise);
  EXPECT_NEAR(p.noise, kNoise, 0.35 * kNoise) << p.noise_source;
  EXPECT_GT(p.setting_scatter, 5.0 * kNoise) << p.noise_source;
  EXPECT_LT(p.setting_scatter, 25.0 * kNoise) << p.noise_source;
  EXPECT_NE(p.noise_source.find("share an offset"), std::string::npos) << p.noise_source;
  const PreparedTrial none = prepared_sweep(0.8, 0.0);
  EXPECT_LT(none.setting_scatter, 2.0 * kNoise) << none.noise_source;
}

TEST_F(AlternatingSweepNoise, SuccessiveDifferencesWhereTheSidesDifferMore) {
  // A side offset of up to 0.5 N m growing with the pressure (a large hysteresis; a setting's offset takes out only
  // what its readings share) and no misfit: the successive differences are the smaller.
  const PreparedTrial p = prepared_sweep(1.0, 0.5);
  EXPECT_EQ(p.noise_source.find("either side"), std::string::npos) << p.noise_source;
  EXPECT_LT(p.noise, 0.2);
}

// A sweep's reading moves with the relaxed wrist only where it includes the wrist's torque (conventions.h): the
// muscle's torque alone and the reading less its 0 kPa baseline do not, and the relaxed wrist is not scored on them.
TEST_F(AlternatingSweepNoise, TheRelaxedWristActsOnASweepOnlyWhereItsReadingIncludesTheWrist) {
  const ModelVariant nominal{.device = sim::paper_device()};
  ModelVariant stiffer = nominal;
  std::vector<double> values = fit_start(EffectId::kPassiveWrist, nominal.device);
  values[0] = 2.0;  // stiffness_scale
  apply_effect(EffectId::kPassiveWrist, values, stiffer);
  const EffectSpec& wrist = effect_spec(EffectId::kPassiveWrist);
  for (const std::string convention : {"muscle", "baseline_subtracted", "muscle+passive_wrist",
                                       "muscle+passive_wrist+hand_weight", "muscle+hand_weight"}) {
    prepared_sweep(0.8, 0.0);
    data_.trials[0].conventions.torque = *torque_includes_from_name(convention);
    const PreparedTrial p = prepare(data_, engine_, nominal).at(0);
    const bool includes_wrist = convention.find("passive_wrist") != std::string::npos;
    EXPECT_EQ(acts_on(wrist, p), includes_wrist) << convention;
    EXPECT_EQ(engine_.predict(p, stiffer, false) != engine_.predict(p, nominal, false), includes_wrist) << convention;
    EXPECT_TRUE(acts_on(effect_spec(EffectId::kFpamParams), p)) << convention;
  }
}

// The sweep's held-out part is a checkerboard of held angle and pressure level (replay.cc, prepare_sweep): every held
// angle, a bootstrap unit, has points in both parts, and the parity follows the level, not the regulator's jitter.
TEST_F(AlternatingSweepNoise, HeldOutAsACheckerboardOfAngleAndPressureLevel) {
  Trial trial{.kind = TrialKind::kTorqueSweep, .name = "sweep", .file = "sweep.csv"};
  for (const int repetition : {1, 2})
    for (int a = 0; a < 4; ++a)
      for (int p = 0; p < 5; ++p)
        trial.sweep.push_back({.angle = units::deg_to_rad(-30.0 + 20.0 * a + 0.3 * repetition),
                               .pressure = units::kpa_to_pa(34.0 * p + (p > 0 ? 1.5 * ((a + repetition) % 3) : 0.0)),
                               .torque = 0.1,
                               .repetition = repetition});
  data_.trials = {trial};
  const PreparedTrial prepared = prepare(data_, engine_, ModelVariant{.device = sim::paper_device()}).at(0);
  std::map<int, std::pair<int, int>> held_and_kept;  // per unit
  for (std::size_t i = 0; i < prepared.points.size(); ++i) {
    const int a = static_cast<int>(i / 5) % 4, level = static_cast<int>(i % 5);
    EXPECT_EQ(prepared.points[i].heldout, (a + level) % 2 == 1) << "angle " << a << ", level " << level;
    (prepared.points[i].heldout ? held_and_kept[prepared.points[i].unit].first
                                : held_and_kept[prepared.points[i].unit].second)++;
  }
  EXPECT_EQ(held_and_kept.size(), 4u);
  for (const auto& [unit, counts] : held_and_kept) EXPECT_TRUE(counts.first > 0 && counts.second > 0) << unit;
}

// A range of motion whose angles were zeroed between conditions, read in the log's order (ReplayEngine::predict_rom):
// where the previous condition's muscle still held a share r of its pressure when they were zeroed (a slow vent), the
// zero is that muscle's settled angle at r times its pressure, and each reading is off by it.
class RangeOfMotionCarryOver : public ::testing::Test {
 protected:
  static Trial rom_trial(const std::vector<std::pair<sim::MuscleIndex, double>>& rows_kpa) {
    Trial t{.kind = TrialKind::kRangeOfMotion, .name = "rom", .file = "rom"};
    t.conventions.angles_zeroed_at_start = true;
    for (const int repetition : {1, 2}) {
      for (const auto& [muscle, kpa] : rows_kpa)
        t.rom.push_back({.muscle = muscle, .pressure = units::kpa_to_pa(kpa), .repetition = repetition});
    }
    return t;
  }
  // `trial` prepared alone (data_ holds it, as the prepared trial points into it).
  PreparedTrial prepared(const Trial& trial) {
    data_.trials = {trial};
    return prepare(data_, engine_, ModelVariant{.device = sim::paper_device()}).at(0);
  }
  std::vector<double> readings(const Trial& trial, double residual_fraction) {
    const ModelVariant variant{.device = sim::paper_device(), .rom_residual_fraction = residual_fraction};
    return engine_.predict(prepared(trial), variant, false);
  }
  RealData data_;
  ReplayEngine engine_{sim::PluginSet::Default()};
};

TEST_F(RangeOfMotionCarryOver, TheZeroIsTakenWithThePreviousMuscleNotYetVented) {
  constexpr double kResidual = 0.4;
  const Trial trial = rom_trial({{sim::kFlexor, 68.0}, {sim::kFlexor, 137.0}, {sim::kExtensor, 34.0}});
  const std::vector<double> vented = readings(trial, 0.0);
  const std::vector<double> carried = readings(trial, kResidual);
  // The first row starts from rest.
  EXPECT_DOUBLE_EQ(carried[0], vented[0]);
  // The flexor at 137 kPa, zeroed with itself still at 0.4 x 68 kPa: its reading less that pose's angle.
  const double residual_angle = readings(rom_trial({{sim::kFlexor, kResidual * 68.0}}), 0.0)[0];
  EXPECT_GT(residual_angle, 1.0);
  EXPECT_NEAR(carried[1], vented[1] - residual_angle, 1e-3);
  // The extensor after the flexor at 137 kPa: zeroed with the wrist flexed, so it reads further (the flexor's r^2
  // share at the limit takes back less than the zero gave).
  EXPECT_GT(carried[2], vented[2] + 1.0);
  // The next repetition's flexor, zeroed with the extensor still pulling, reads further too.
  EXPECT_GT(carried[3], vented[3]);
}

// Settled limits do not depend on the regulators: they reach a range of motion only through the zero.
TEST_F(RangeOfMotionCarryOver, TheRegulatorsActOnlyWhereTheAnglesWereZeroedBeforeEachCondition) {
  Trial trial = rom_trial({{sim::kFlexor, 137.0}, {sim::kExtensor, 137.0}});
  const EffectSpec& regulator = effect_spec(EffectId::kRegulatorLag);
  for (const bool zeroed : {true, false}) {
    trial.conventions.angles_zeroed_at_start = zeroed;
    EXPECT_EQ(acts_on(regulator, prepared(trial)), zeroed);
    if (!zeroed) {
      EXPECT_EQ(readings(trial, 0.5), readings(trial, 0.0));
    }
  }
}

// A settled limit does not depend on how fast the regulators reach their pressures: a regulator_lag fit's time
// constants read the same limits from one settle per pose (ReplayEngine::settle).
TEST_F(RangeOfMotionCarryOver, TheRegulatorsResponseDoesNotResettleTheLimits) {
  const Trial trial = rom_trial({{sim::kFlexor, 137.0}, {sim::kExtensor, 68.0}});
  const PreparedTrial p = prepared(trial);
  ModelVariant variant{.device = sim::paper_device(), .rom_residual_fraction = 0.3};
  const std::vector<double> nominal = engine_.predict(p, variant, false);
  const auto settles = engine_.stats().settles;
  variant.device.regulator.time_constant = 0.4;
  variant.device.regulator.vent_time_constant = 1.2;
  variant.device.regulator.second_order_time = 0.1;
  EXPECT_EQ(engine_.predict(p, variant, false), nominal);
  EXPECT_EQ(engine_.stats().settles, settles);
  // The residual pressure is the carry-over's own: another fraction settles again.
  variant.rom_residual_fraction = 0.5;
  EXPECT_NE(engine_.predict(p, variant, false), nominal);
  EXPECT_GT(engine_.stats().settles, settles);
}

}  // namespace
}  // namespace softwrist::diagnosis
