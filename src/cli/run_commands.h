#pragma once
// `softwrist run CONFIG` and `softwrist merge`: experiments from their config files, on threads or in shards
// (src/experiments/runner.h).
#include <ostream>

#include <CLI/CLI.hpp>

namespace softwrist::cli {

void add_run_commands(CLI::App& app, std::ostream& out, std::ostream& err);

}  // namespace softwrist::cli
