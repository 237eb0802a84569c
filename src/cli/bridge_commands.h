#pragma once
// `softwrist emulate` (the device emulator on a pseudo-terminal) and `softwrist trial` (a tracking experiment on
// the exosuit through the bridge).

#include <functional>
#include <ostream>
#include <string>

#include <CLI/CLI.hpp>

#include "bridge/bridge_plant.h"
#include "physics/exosuit_layout.h"

namespace softwrist::cli {

// Where a command reaches the exosuit: a serial device, or the emulator on one simulated clock in this process.
struct BridgeCommandOptions {
  std::string device;
  std::string emulator;
  std::string firmware;  // with emulator: the real firmware on a simulated board in front of its plant
  double max_kpa = physics::kRegulatorMaxPressureKpa;
  int timeout_ms = 40;
  int baud = 115200;
};
// --device / --emulator, --max-kpa, --timeout-ms, --baud.
void add_bridge_options(CLI::App& command, BridgeCommandOptions& options);
// Opens the plant the options name (UsageError for bad ones) and hands it to `use` with a description of where it is.
void on_bridge(const BridgeCommandOptions& options,
               const std::function<void(bridge::BridgePlant& plant, const std::string& where)>& use);

void add_bridge_commands(CLI::App& app, std::ostream& out, std::ostream& err);
// `softwrist bench bridge` (bridge_bench.cc), under the bench command.
void add_bridge_bench(CLI::App& bench, std::ostream& out);
// `softwrist bench hil` (hil_bench.cc).
void add_hil_bench(CLI::App& bench, std::ostream& out);

}  // namespace softwrist::cli
