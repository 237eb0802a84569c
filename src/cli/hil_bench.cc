// `softwrist bench hil`: the firmware in the loop's speed, timing and size (src/hil/avr_board.h).
#include <filesystem>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "cli/arguments.h"
#include "cli/bridge_commands.h"
#include "hil/avr_board.h"
#include "hil/side_by_side.h"

namespace softwrist::cli {
namespace {

namespace fs = std::filesystem;

struct HilBenchOptions {
  std::string config = "experiments/planar_rehearsal.json";
  std::string emulator = "experiments/emulator/nominal.json";
  std::string firmware = "build/firmware/softwrist_fw.elf";
  std::string out = "out/bench_hil";
  bool json = false;
};

void bench_hil(const HilBenchOptions& o, std::ostream& out) {
  const experiments::ExperimentConfig config = experiments::load_experiment_config(o.config);
  const bridge::EmulatorConfig plant = bridge::load_emulator_config(o.emulator);
  const hil::SideBySide run = hil::run_side_by_side(
      config, plant, o.firmware, {.controllers = {"paper"}, .repetitions = 1, .overwrite = true}, fs::path(o.out));
  const hil::BoardStats& s = run.board;
  const double avr_s = hil::avr_seconds(s.cycles), wall_s = run.firmware_wall_s;
  const hil::FirmwareSize size = hil::firmware_size(o.firmware);
  const hil::AngleDifference& diff = run.angles;
  const auto us = [](double cycles) { return hil::avr_microseconds(cycles); };
  const nlohmann::json result = {
      {"experiment", o.config},
      {"avr_time_s", avr_s},
      {"wall_s", wall_s},
      {"realtime_factor", avr_s / wall_s},
      {"loop_max_us", us(static_cast<double>(s.loop_max_cycles))},
      {"loop_mean_us", s.loops > 0 ? us(static_cast<double>(s.loop_cycles_total) / static_cast<double>(s.loops)) : 0.0},
      {"loops", s.loops},
      {"i2c_read_us", s.i2c_read_transactions > 0 ? us(static_cast<double>(s.i2c_read_cycles_total) /
                                                       static_cast<double>(s.i2c_read_transactions))
                                                  : 0.0},
      {"i2c_read_max_us", us(static_cast<double>(s.i2c_read_max_cycles))},
      {"serial_bytes_per_s", static_cast<double>(s.bytes_from_avr) / avr_s},
      {"flash_bytes", size.flash_bytes},
      {"ram_bytes", size.ram_bytes},
      {"stack_headroom_bytes", s.stack_headroom_bytes},
      {"resets", s.resets},
      {"rms_vs_sim_deg", diff.rms_deg},
      {"max_vs_sim_deg", diff.max_deg},
      {"rows_compared", diff.rows}};
  if (o.json) {
    out << result.dump(2) << '\n';
    return;
  }
  out << fmt::format(
      "firmware in the loop: {:.1f} s of AVR time in {:.1f} s ({:.2f}x real time); loop {:.0f} us mean, {:.0f} us "
      "max; an IMU read {:.0f} us; {:.0f} bytes/s to the host; flash {} B, RAM {} B, stack headroom {} B; measured "
      "angles against the emulator: RMS {:.3f} deg, max {:.2f} deg over {} rows\n",
      avr_s, wall_s, avr_s / wall_s, result["loop_mean_us"].get<double>(), result["loop_max_us"].get<double>(),
      result["i2c_read_us"].get<double>(), result["serial_bytes_per_s"].get<double>(), size.flash_bytes, size.ram_bytes,
      s.stack_headroom_bytes, diff.rms_deg, diff.max_deg, diff.rows);
}

}  // namespace

void add_hil_bench(CLI::App& bench, std::ostream& out) {
  auto o = std::make_shared<HilBenchOptions>();
  auto* command = bench.add_subcommand(
      "hil",
      "The firmware in the loop: speed against real time, loop and I2C timing at 16 MHz, size, and the planar "
      "rehearsal's angles against the emulator's");
  command->add_option("--firmware", o->firmware, "The firmware ELF (scripts/build_firmware.sh)");
  command->add_option("--config", o->config, "A tracking experiment")->check(CLI::ExistingFile);
  command->add_option("--emulator", o->emulator, "The plant (an emulator config)")->check(CLI::ExistingFile);
  command->add_option("--out", o->out, "Where the two trials go");
  command->add_flag("--json", o->json, "Print the figures as JSON");
  command->callback([o, &out] { bench_hil(*o, out); });
}

}  // namespace softwrist::cli
