#include "cli/report_command.h"

#include <memory>

#include <fmt/format.h>

#include "report/html_report.h"

namespace softwrist::cli {
namespace {

struct ReportCommandOptions {
  std::string run_dir;
  std::string out;
  bool no_plots = false;
  bool no_renders = false;
};

}  // namespace

void add_report_command(CLI::App& app, std::ostream& out) {
  auto options = std::make_shared<ReportCommandOptions>();
  auto* report = app.add_subcommand(
      "report",
      "One HTML page of a run directory: what was run, metrics beside the paper's, plots (matplotlib), renders "
      "(OSMesa)");
  report->add_option("run_dir", options->run_dir, "A run directory (softwrist run --out)")->required();
  report->add_option("--out", options->out, "Where the page and its PNGs go (default RUN_DIR/report)");
  report->add_flag("--no-plots", options->no_plots, "Without plots (no python3-matplotlib needed)");
  report->add_flag("--no-renders", options->no_renders, "Without renders of the run's moments (no OSMesa needed)");
  report->callback([options, &out] {
    const auto result = report::write_report(
        options->run_dir, {.out = options->out, .plots = !options->no_plots, .renders = !options->no_renders});
    out << fmt::format("{} ({} plots, {} renders)\n", result.page.string(), result.plots.size(), result.renders.size());
  });
}

}  // namespace softwrist::cli
