#include "hil/side_by_side.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "bridge_apps/lockstep_link.h"
#include "io/csv.h"

namespace softwrist::hil {
namespace {

// The trial on `device` at the end of the rig's line, into `out`.
void run_on(bridge::LineDevice& device, const experiments::ExperimentConfig& config, bridge::TrialOptions trial,
            const std::filesystem::path& out, const char* what) {
  bridge::LockstepLink rig(device);
  bridge::BridgePlant host(rig.open_host(), rig, {});
  trial.out = out;
  const bridge::TrialResult r = bridge::run_trial(config, host, trial);
  if (r.fault) throw std::runtime_error(fmt::format("the trial {} stopped: {}", what, *r.fault));
}

}  // namespace

AngleDifference measured_angle_difference(const std::filesystem::path& log_a, const std::filesystem::path& log_b) {
  const io::CsvTable a = io::CsvTable::Read(log_a), b = io::CsvTable::Read(log_b);
  if (a.row_count() != b.row_count()) {
    throw std::runtime_error(fmt::format("{} has {} rows, {} has {}: not the same run", log_a.string(), a.row_count(),
                                         log_b.string(), b.row_count()));
  }
  AngleDifference d{.rows = a.row_count()};
  double sum = 0.0;
  for (const char* name : {"measured_fe_deg", "measured_ur_deg"}) {
    const int ca = a.column(name), cb = b.column(name);
    for (std::size_t r = 0; r < a.row_count(); ++r) {
      const double diff = a.number(r, ca) - b.number(r, cb);
      sum += diff * diff;
      d.max_deg = std::max(d.max_deg, std::abs(diff));
    }
  }
  d.rms_deg = d.rows > 0 ? std::sqrt(sum / (2.0 * static_cast<double>(d.rows))) : 0.0;
  return d;
}

SideBySide run_side_by_side(const experiments::ExperimentConfig& config, const bridge::EmulatorConfig& plant,
                            const std::filesystem::path& firmware, bridge::TrialOptions trial,
                            const std::filesystem::path& dir) {
  SideBySide out{.firmware_dir = dir / "hil", .emulator_dir = dir / "emulator"};
  {
    AvrBoard board(firmware, plant);
    const auto start = std::chrono::steady_clock::now();
    run_on(board, config, trial, out.firmware_dir, "through the firmware");
    out.firmware_wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    out.board = board.stats();
  }
  bridge::DeviceEmulator emulator(plant);
  run_on(emulator, config, trial, out.emulator_dir, "on the emulator");
  out.angles = measured_angle_difference(out.firmware_dir / "trials.csv", out.emulator_dir / "trials.csv");
  return out;
}

}  // namespace softwrist::hil
