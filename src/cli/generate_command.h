#pragma once
// `softwrist generate`: a data set from the independent simulated exosuit (src/independent_device), as real rigs
// give it: the torque rig's sweep and tensile test, the prototype's range of motion and closed-loop tracking, CSVs
// with coloured and quantised sensor noise, a manifest of the conventions a user states at import, and the truth.
#include <ostream>

#include <CLI/CLI.hpp>

namespace softwrist::cli {

void add_generate_command(CLI::App& app, std::ostream& out);

}  // namespace softwrist::cli
