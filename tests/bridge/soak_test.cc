// The long trial, short: a minute of tracking through the bridge against the emulator over a link that breaks every
// few seconds (cuts, garbage both ways, stalls), in simulated time (the lock-step rig): every fault ends with the
// device vented within 50 ms, exactly and the same on every machine; every trial's log reads back whole; the
// regulators never exceed their limit. (`softwrist soak` runs the hour in real time; the README gives its figures.)

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "bridge_apps/soak.h"
#include "support/scratch_dir_test.h"

namespace softwrist::bridge {
namespace {

class Soak : public testing::ScratchDirTest {};

TEST_F(Soak, EveryFaultVentsWithin50MsAndEveryLogReadsBackWhole) {
  const auto config = experiments::load_experiment_config(SOFTWRIST_SOURCE_DIR "/experiments/planar_rehearsal.json");
  const auto emulator = load_emulator_config(SOFTWRIST_SOURCE_DIR "/experiments/emulator/realistic.json");
  const SoakResult result = run_soak(config, emulator,
                                     {.duration_s = 60.0,
                                      .out = dir_,
                                      .faults = {.mean_interval_s = 4.0, .seed = 3},
                                      .simulated_time = true,
                                      .memory_sample_s = 5.0});
  for (const auto& failure : result.failures) ADD_FAILURE() << failure;
  EXPECT_GE(result.faults.size(), 6u);
  EXPECT_GE(result.trials.size(), 3u);
  int vented_by_the_fault = 0;  // faults that met a pressurised device (not one resting, vented already)
  for (const auto& f : result.faults) vented_by_the_fault += f.fault.device_vented_at_onset ? 0 : 1;
  EXPECT_GE(vented_by_the_fault, 3);
  long rows = 0;
  for (const auto& t : result.trials) rows += t.rows;
  EXPECT_GT(rows, 1000);
  EXPECT_LE(result.emulator.max_output_dkpa, emulator.limits.max_dkpa);
  EXPECT_NEAR(result.duration_s, 60.0, 1.0);
}

}  // namespace
}  // namespace softwrist::bridge
