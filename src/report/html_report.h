#pragma once
// `softwrist report`: one HTML page per run directory, with the PNGs beside it. What was run (config, model and
// config hashes, software version), the metrics next to the paper's, and plots made by matplotlib from the run's
// own files (plot_run.py, run with python3), and offscreen renders of the run's moments (run_moments.h). Every
// number on the page comes from the run directory.

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace softwrist::report {

struct ReportOptions {
  std::filesystem::path out;  // default: <run>/report
  bool plots = true;          // false: the page without plots (no python3 needed)
  bool renders = true;        // false: the page without renders of the run's moments (no OSMesa needed)
};

struct ReportResult {
  std::filesystem::path page;
  std::vector<std::string> plots;    // file names beside the page
  std::vector<std::string> renders;  // file names beside the page
};

// Throws std::runtime_error naming the problem: not a run directory, a missing or malformed trials.json or
// summary.json, the plotting failing (python3 or python3-matplotlib missing).
ReportResult write_report(const std::filesystem::path& run_dir, const ReportOptions& options = {});

// The metrics table of a summary: rows of {quantity [unit], softwrist, paper}, by the run's kind.
std::vector<std::array<std::string, 3>> metric_rows(const std::string& kind, const nlohmann::json& summary);
// The page's summary box: the headline rows of that table as sentences, the same numbers.
std::vector<std::string> summary_lines(const std::string& kind, const nlohmann::json& summary);

std::string html_escape(const std::string& text);

// The figures a plot script listed in DIR/plots.json, in page order: a <figure> with its caption each. Appends the
// files to `files`; throws naming a missing or malformed plots.json, or a listed plot that was not written.
std::string plot_figures(const std::filesystem::path& dir, std::vector<std::string>& files);

// Runs one of the report's matplotlib scripts (src/report/NAME, or where it is installed) with `args`; throws
// naming the script and how to do without plots.
void run_plot_script(const std::string& name, const std::vector<std::string>& args);

}  // namespace softwrist::report
