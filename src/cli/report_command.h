#pragma once
// `softwrist report RUN_DIR [--out DIR] [--no-plots]`: the run's HTML report (report/html_report.h).

#include <ostream>

#include <CLI/CLI.hpp>

namespace softwrist::cli {

void add_report_command(CLI::App& app, std::ostream& out);

}  // namespace softwrist::cli
