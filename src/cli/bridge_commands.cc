#include "cli/bridge_commands.h"

#include <chrono>
#include <memory>
#include <optional>
#include <thread>

#include <fmt/format.h>

#include "bridge/bridge_plant.h"
#include "bridge_apps/device_emulator.h"
#include "bridge_apps/hardware_trial.h"
#include "bridge_apps/lockstep_link.h"
#include "bridge_apps/soak.h"
#include "cli/arguments.h"
#include "cli/stop_signals.h"
#include "experiments/experiment.h"
#include "experiments/tracking.h"
#include "hil/avr_board.h"
#include "physics/exosuit_layout.h"

namespace softwrist::cli {
namespace {

struct EmulateOptions {
  std::string config;
  std::string link;
  double duration_s = 0.0;
};

struct TrialCommandOptions {
  std::string config;
  BridgeCommandOptions bridge;
  std::string out;
  std::string model;  // the model_based controller's placement file
  std::vector<std::string> controllers;
  int repetitions = 0;
  double rest_s = 1.0;
  bool overwrite = false;
};

// The path a user gives the trial: a symbolic link to the emulator's pseudo-terminal. An existing file that is not
// such a link is never replaced.
void make_link(const std::filesystem::path& link, const std::string& target) {
  if (std::filesystem::is_symlink(link)) std::filesystem::remove(link);
  if (std::filesystem::exists(link))
    throw UsageError(fmt::format("--link {}: exists and is not a symbolic link", link.string()));
  std::filesystem::create_symlink(target, link);
}

void emulate(const EmulateOptions& options, std::ostream& out) {
  if (options.duration_s < 0.0) throw UsageError("--duration-s must be >= 0");
  const bridge::EmulatorConfig config = bridge::load_emulator_config(options.config);
  bridge::DeviceEmulator emulator(config);
  bridge::PseudoTerminal pty = bridge::PseudoTerminal::Open();
  // Holding the slave side open keeps the pseudo-terminal alive between hosts (each trial opens and closes it).
  const bridge::SerialPort keeper = bridge::SerialPort::Open(pty.slave_path);
  if (!options.link.empty()) make_link(options.link, pty.slave_path);
  out << fmt::format("device emulator: {} on {}{}\n", config.model.string(), pty.slave_path,
                     options.link.empty() ? "" : fmt::format(" (linked from {})", options.link));
  out << "  run a trial with: softwrist trial experiments/<name>.json --device "
      << (options.link.empty() ? pty.slave_path : options.link) << "\n  stop with Ctrl-C\n";
  out.flush();

  StopSignals signals;
  std::atomic<bool> stop{false};
  std::thread server([&] { emulator.serve(std::move(pty.master), stop); });
  const auto start = std::chrono::steady_clock::now();
  while (!signals.requested.load() && !emulator.failed() &&
         (options.duration_s <= 0.0 ||
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() < options.duration_s)) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  stop.store(true);
  server.join();
  if (!options.link.empty() && std::filesystem::is_symlink(options.link)) std::filesystem::remove(options.link);
  const bridge::EmulatorStats s = emulator.stats();
  out << fmt::format(
      "device emulator stopped: {} sessions, {} packets accepted, {} rejected, {} data packets sent, "
      "{} bytes dropped, {} vents\n",
      s.sessions, s.packets_accepted, s.packets_rejected, s.data_sent, s.bytes_dropped, s.vents.size());
  if (!s.stopped_by.empty()) throw std::runtime_error("device emulator: the simulated exosuit failed: " + s.stopped_by);
}

// The trial on `plant`, reported as on `where` (the serial device, or the emulator's config).
void run_trial_on(const TrialCommandOptions& options, const experiments::ExperimentConfig& config,
                  bridge::BridgePlant& plant, const std::string& where, std::ostream& out, std::ostream& err) {
  StopSignals signals;
  const std::filesystem::path dir =
      options.out.empty() ? std::filesystem::path("trials") / config.name : std::filesystem::path(options.out);
  bridge::TrialOptions trial_options{.out = dir,
                                     .controllers = options.controllers,
                                     .overwrite = options.overwrite,
                                     .interrupt = &signals.requested,
                                     .progress = &err};
  if (options.repetitions > 0) trial_options.repetitions = options.repetitions;
  trial_options.rest_s = options.rest_s;  // the subject holds the wrist at neutral meanwhile
  const bridge::TrialResult result = bridge::run_trial(config, plant, trial_options);
  out << fmt::format("{}: {} of {} runs on {}, log {}/trials.csv, bridge record {}/bridge.json{}\n", dir.string(),
                     result.runs_completed, result.runs_planned, where, dir.string(), dir.string(),
                     result.runs_completed > 0 ? fmt::format(", summary {}/summary.json", dir.string()) : "");
  if (result.fault) {
    throw std::runtime_error(fmt::format(
        "the trial stopped, vented: {}\n  every row measured before it is in {}/trials.csv; run the remaining runs "
        "again with --out <another dir> (--controller and --repetitions choose them)",
        *result.fault, dir.string()));
  }
}

bridge::BridgeOptions check_bridge_options(const BridgeCommandOptions& o) {
  if (!(o.max_kpa > 0.0 && o.max_kpa <= physics::kRegulatorMaxPressureKpa)) {
    throw UsageError("--max-kpa must be in (0, 137]: the QB3 regulators' range");
  }
  if (o.device.empty() == o.emulator.empty()) throw UsageError("give one of --device and --emulator");
  if (o.timeout_ms < 1 || o.timeout_ms > 1000) throw UsageError("--timeout-ms must be 1..1000");
  bridge::BridgeOptions b;
  b.limits.max_dkpa = static_cast<int32_t>(o.max_kpa * 10.0);
  b.limits.timeout_ms = static_cast<std::uint32_t>(o.timeout_ms);
  return b;
}

// The host on the lock-step rig (issue 27) with `device` at the end of its line: the same firmware rules, bytes and
// host, on one simulated clock, so the result does not depend on how busy the machine is.
void on_lockstep(bridge::LineDevice& device, int baud, const bridge::BridgeOptions& bridge_options,
                 const std::string& where,
                 const std::function<void(bridge::BridgePlant& plant, const std::string& where)>& use) {
  bridge::LockstepLink rig(device, {.baud = baud});
  bridge::BridgePlant plant(rig.open_host(), rig, bridge_options);
  use(plant, where);
}

}  // namespace

void on_bridge(const BridgeCommandOptions& o,
               const std::function<void(bridge::BridgePlant& plant, const std::string& where)>& use) {
  const bridge::BridgeOptions bridge_options = check_bridge_options(o);
  if (!o.emulator.empty()) {
    // With --firmware, the real firmware on a simulated board in front of the same plant (docs/hil.md).
    const bridge::EmulatorConfig config = bridge::load_emulator_config(o.emulator);
    if (o.firmware.empty()) {
      bridge::DeviceEmulator emulator(config);
      on_lockstep(emulator, o.baud, bridge_options, fmt::format("the emulator {} (simulated time)", o.emulator), use);
    } else {
      hil::AvrBoard board(o.firmware, config);
      on_lockstep(
          board, o.baud, bridge_options,
          fmt::format("the firmware {} on a simulated ATmega328P, plant {} (simulated time)", o.firmware, o.emulator),
          use);
    }
    return;
  }
  bridge::BridgePlant plant(bridge::SerialPort::Open(o.device, o.baud), bridge_options);
  use(plant, o.device);
}

void add_bridge_options(CLI::App& command, BridgeCommandOptions& o) {
  auto* device_option = command.add_option("--device", o.device, "Serial device: /dev/ttyACM0, or the emulator's link");
  command
      .add_option("--emulator", o.emulator,
                  "Instead of --device: the device emulator of this config (softwrist.emulator/1) and the host on "
                  "one simulated clock, in this process (the same result on any machine, however busy)")
      ->check(CLI::ExistingFile)
      ->excludes(device_option);
  command
      .add_option("--firmware", o.firmware,
                  "With --emulator: the real firmware (an ELF, scripts/build_firmware.sh) on a simulated ATmega328P "
                  "in front of the emulator config's plant (docs/hil.md)")
      ->check(CLI::ExistingFile)
      ->excludes(device_option);
  command.add_option("--max-kpa", o.max_kpa, "The host's pressure limit (the device's applies too)");
  command.add_option("--timeout-ms", o.timeout_ms,
                     "The host's watchdog: no valid data, or no command of its own, for this long stops the "
                     "trial (the device's applies too; the shorter wins); default 40");
  command.add_option("--baud", o.baud, "Serial speed");
}

namespace {

void trial(const TrialCommandOptions& options, std::ostream& out, std::ostream& err) {
  if (options.repetitions < 0) throw UsageError("--repetitions must be >= 1");
  if (!(options.rest_s >= 0.0)) throw UsageError("--rest-s must be >= 0");
  experiments::ExperimentConfig config = experiments::load_experiment_config(options.config);
  if (!options.model.empty()) {
    if (!experiments::set_controller_model(config.json, std::filesystem::absolute(options.model))) {
      throw UsageError(fmt::format("--model: {} has no model_based controller to give it to", options.config));
    }
  }
  on_bridge(options.bridge, [&](bridge::BridgePlant& plant, const std::string& where) {
    run_trial_on(options, config, plant, where, out, err);
  });
}

struct HilCommandOptions {
  TrialCommandOptions trial;
  std::string firmware = "build/firmware/softwrist_fw.elf";
  std::string emulator = "experiments/emulator/nominal.json";  // the plant: model, posture, seed, IMU noise
  std::string placement;                                       // instead of the emulator config's model
};

// `softwrist hil`: the trial through the real firmware on a simulated board (src/hil/avr_board.h).
void hil(const HilCommandOptions& options, std::ostream& out, std::ostream& err) {
  if (options.trial.repetitions < 0) throw UsageError("--repetitions must be >= 1");
  experiments::ExperimentConfig config = experiments::load_experiment_config(options.trial.config);
  bridge::EmulatorConfig plant = bridge::load_emulator_config(options.emulator);
  if (!options.placement.empty()) {
    plant.model = std::filesystem::absolute(options.placement);
    config.json["model"] = plant.model.string();
  }
  hil::AvrBoard board(options.firmware, plant);
  on_lockstep(board, options.trial.bridge.baud, {},
              fmt::format("the firmware {} on a simulated ATmega328P (simulated time)", options.firmware),
              [&](bridge::BridgePlant& bridge_plant, const std::string& where) {
                run_trial_on(options.trial, config, bridge_plant, where, out, err);
              });
  const hil::BoardStats& s = board.stats();
  out << fmt::format(
      "board: {:.1f} s of AVR time, {} resets, {} bytes from the firmware, {} to it, {} IMU reads; loop max {:.0f} us, "
      "stack headroom {} bytes\n",
      hil::avr_seconds(s.cycles), s.resets, s.bytes_from_avr, s.bytes_to_avr, s.i2c_reads,
      hil::avr_microseconds(static_cast<double>(s.loop_max_cycles)), s.stack_headroom_bytes);
}

struct SoakCommandOptions {
  std::string config = "experiments/planar_rehearsal.json";
  std::string emulator = "experiments/emulator/realistic.json";
  std::string out = "out/soak";
  double duration_s = 3600.0;
  double fault_interval_s = 20.0;
  std::uint64_t seed = 1;
  bool simulated_time = false;
};

void soak(const SoakCommandOptions& options, std::ostream& out, std::ostream& err) {
  if (!(options.duration_s > 0.0)) throw UsageError("--duration-s must be > 0");
  if (!(options.fault_interval_s > 0.0)) throw UsageError("--fault-interval-s must be > 0");
  const bridge::SoakResult result = bridge::run_soak(
      experiments::load_experiment_config(options.config), bridge::load_emulator_config(options.emulator),
      {.duration_s = options.duration_s,
       .out = options.out,
       .faults = {.mean_interval_s = options.fault_interval_s, .seed = options.seed},
       .simulated_time = options.simulated_time,
       .progress = &err});
  const nlohmann::json j = bridge::to_json(result);
  const auto& memory = result.memory;
  out << fmt::format(
      "soak ({} time): {:.0f} s, {} trials, {} rows, {} faults {}, slowest vent {:.1f} ms after its fault; heap in "
      "use {:.2f} MB at the start, {:.2f} MB at the end (resident {:.1f} -> {:.1f} MB); {}/soak.json\n",
      options.simulated_time ? "simulated" : "real", result.duration_s, result.trials.size(), j["rows"].get<long>(),
      result.faults.size(), j["faults_by_kind"].dump(), j["max_vent_after_ms"].get<double>(),
      memory.front().heap_bytes / 1e6, memory.back().heap_bytes / 1e6, memory.front().resident_bytes / 1e6,
      memory.back().resident_bytes / 1e6, options.out);
  if (!result.passed()) {
    std::string list;
    for (const auto& f : result.failures) list += "\n  " + f;
    throw std::runtime_error("soak: failed:" + list);
  }
}

}  // namespace

void add_bridge_commands(CLI::App& app, std::ostream& out, std::ostream& err) {
  auto emulate_options = std::make_shared<EmulateOptions>();
  auto* emulate_command = app.add_subcommand(
      "emulate",
      "Run the device emulator on a pseudo-terminal: the firmware's protocol and safety rules in front of "
      "a simulated exosuit with the extra effects of its config (docs/emulator.md)");
  emulate_command->add_option("config", emulate_options->config, "Emulator config (JSON, softwrist.emulator/1)")
      ->required()
      ->check(CLI::ExistingFile);
  emulate_command->add_option(
      "--link", emulate_options->link,
      "Also reach the pseudo-terminal through this path (a symbolic link), e.g. /tmp/softwrist-device");
  emulate_command->add_option("--duration-s", emulate_options->duration_s, "Stop after this long; default: at Ctrl-C");
  emulate_command->callback([emulate_options, &out] { emulate(*emulate_options, out); });

  auto trial_options = std::make_shared<TrialCommandOptions>();
  auto* trial_command =
      app.add_subcommand("trial",
                         "Run a tracking experiment on the exosuit (or the emulator) through the bridge, logging as a "
                         "simulated run does");
  trial_command->add_option("config", trial_options->config, "Tracking experiment config (JSON)")
      ->required()
      ->check(CLI::ExistingFile);
  add_bridge_options(*trial_command, trial_options->bridge);
  trial_command->add_option("--out", trial_options->out, "Trial directory; default trials/<config name>");
  trial_command->add_option("--controller", trial_options->controllers,
                            "Run only this controller (repeatable); default: every controller of the config");
  trial_command->add_option("--repetitions", trial_options->repetitions, "Runs per controller; default: the config's");
  trial_command->add_option("--rest-s", trial_options->rest_s,
                            "Vented pause before each run, while the subject holds the "
                            "wrist at neutral for zeroing [s]");
  trial_command
      ->add_option("--model", trial_options->model,
                   "The model_based controller's model of the device (a placement file, e.g. a calibration's "
                   "calibrated.json); default: the config's")
      ->check(CLI::ExistingFile);
  trial_command->add_flag("--overwrite", trial_options->overwrite, "Replace a trial log already in the directory");
  trial_command->callback([trial_options, &out, &err] { trial(*trial_options, out, err); });

  auto hil_options = std::make_shared<HilCommandOptions>();
  auto* hil_command = app.add_subcommand(
      "hil",
      "Run a tracking experiment through the bridge and the real firmware on a simulated ATmega328P (simavr) driving "
      "the simulated exosuit, in lock-step (docs/hil.md)");
  hil_command->add_option("config", hil_options->trial.config, "Tracking experiment config (JSON)")
      ->required()
      ->check(CLI::ExistingFile);
  hil_command->add_option("--firmware", hil_options->firmware, "The firmware ELF (scripts/build_firmware.sh)");
  hil_command->add_option("--emulator", hil_options->emulator, "The plant: an emulator config (model, posture, noise)")
      ->check(CLI::ExistingFile);
  hil_command->add_option("--placement", hil_options->placement, "The plant's placement file instead of the config's")
      ->check(CLI::ExistingFile);
  hil_command->add_option("--out", hil_options->trial.out, "Trial directory; default trials/<config name>");
  hil_command->add_option("--controller", hil_options->trial.controllers, "Run only this controller (repeatable)");
  hil_command->add_option("--repetitions", hil_options->trial.repetitions,
                          "Runs per controller; default: the config's");
  hil_command->add_flag("--overwrite", hil_options->trial.overwrite, "Replace a trial log already in the directory");
  hil_command->callback([hil_options, &out, &err] { hil(*hil_options, out, err); });

  auto soak_options = std::make_shared<SoakCommandOptions>();
  auto* soak_command = app.add_subcommand(
      "soak",
      "The long trial: tracking through the bridge against the emulator over a link with random faults; "
      "checks that every fault vents within 50 ms, every log reads back whole, memory stays flat");
  soak_command->add_option("--duration-s", soak_options->duration_s, "How long; default 3600");
  soak_command->add_option("--fault-interval-s", soak_options->fault_interval_s,
                           "Mean time between faults; default 20");
  soak_command->add_option("--seed", soak_options->seed, "Seed of the fault schedule");
  soak_command->add_option("--out", soak_options->out, "Directory for the trials and soak.json; default out/soak");
  soak_command->add_flag("--simulated-time", soak_options->simulated_time,
                         "Run the device, the line and the host on one simulated clock (the lock-step rig): exact "
                         "and the same on any machine; default: real time over pseudo-terminals");
  soak_command->add_option("--config", soak_options->config, "Tracking experiment; default the planar rehearsal")
      ->check(CLI::ExistingFile);
  soak_command->add_option("--emulator", soak_options->emulator, "Emulator config; default the realistic device")
      ->check(CLI::ExistingFile);
  soak_command->callback([soak_options, &out, &err] { soak(*soak_options, out, err); });
}

}  // namespace softwrist::cli
