#pragma once
// `softwrist calibrate` (the excitation routine through the bridge, the fit of what it identifies, the calibrated
// placement file) and `softwrist bench calibrate` (tracking with the nominal, calibrated and true models).

#include <ostream>

#include <CLI/CLI.hpp>

namespace softwrist::cli {

void add_calibrate_command(CLI::App& app, std::ostream& out, std::ostream& err);
// Under the bench command.
void add_calibrate_bench(CLI::App& bench, std::ostream& out, std::ostream& err);

}  // namespace softwrist::cli
