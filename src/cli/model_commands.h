#pragma once
// `softwrist model ...`: the analytic model of Section Modeling on the command line (torque curves, modeled range
// of motion, and the main job's tables). Placements and lengths in cm, pressures in kPa, angles in degrees, as in
// the paper's tables; converted to SI on entry.

#include <ostream>

#include <CLI/CLI.hpp>

namespace softwrist::cli {

void add_model_commands(CLI::App& app, std::ostream& out);

}  // namespace softwrist::cli
