#pragma once
// `softwrist bench ...`: speed figures printed side by side in one run (ratios, since these machines are noisy).

#include <ostream>

#include <CLI/CLI.hpp>

namespace softwrist::cli {

void add_bench_commands(CLI::App& app, std::ostream& out, std::ostream& err);

}  // namespace softwrist::cli
