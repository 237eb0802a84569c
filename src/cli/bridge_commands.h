#pragma once
// `softwrist emulate` (the device emulator on a pseudo-terminal) and `softwrist trial` (a tracking experiment on
// the exosuit through the bridge).

#include <ostream>

#include <CLI/CLI.hpp>

namespace softwrist::cli {

void add_bridge_commands(CLI::App& app, std::ostream& out, std::ostream& err);
// `softwrist bench bridge` (bridge_bench.cc), under the bench command.
void add_bridge_bench(CLI::App& bench, std::ostream& out);

}  // namespace softwrist::cli
