#pragma once
// One tracking experiment run twice with the same plant: through the firmware on the simulated board, and on the
// device emulator (the firmware's rules in C++), each through the bridge on the lock-step rig. What `softwrist bench
// hil` measures and tests/hil/hil_test.cc checks.

#include <filesystem>

#include "bridge_apps/hardware_trial.h"
#include "hil/avr_board.h"

namespace softwrist::hil {

// How far two trial logs' measured angles lie apart, row by row: RMS and largest difference over both axes [deg] and
// the rows compared.
struct AngleDifference {
  double rms_deg = 0.0, max_deg = 0.0;
  std::size_t rows = 0;
};
// Throws std::runtime_error for logs of different lengths or without the angle columns.
AngleDifference measured_angle_difference(const std::filesystem::path& log_a, const std::filesystem::path& log_b);

struct SideBySide {
  BoardStats board;                                  // the board's, after its run
  double firmware_wall_s = 0.0;                      // host time of the run through the firmware
  std::filesystem::path firmware_dir, emulator_dir;  // DIR/hil and DIR/emulator: each run's trial log and summary
  AngleDifference angles;
};

// Runs `config` with `trial`'s controllers and repetitions (its `out` is replaced) through `firmware` in front of
// `plant` into DIR/hil, then on the emulator of `plant` into DIR/emulator. Throws std::runtime_error naming the run a
// fault stopped.
SideBySide run_side_by_side(const experiments::ExperimentConfig& config, const bridge::EmulatorConfig& plant,
                            const std::filesystem::path& firmware, bridge::TrialOptions trial,
                            const std::filesystem::path& dir);

}  // namespace softwrist::hil
