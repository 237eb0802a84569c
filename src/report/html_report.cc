#include "report/html_report.h"

#include <array>
#include <cstdlib>
#include <fstream>
#include <stdexcept>

#include <fmt/format.h>

#include "io/subprocess.h"
#include "io/text_file.h"
#include "report/page_style.h"
#include "report/pose_renderer.h"
#include "report/run_moments.h"

namespace softwrist::report {
namespace {

namespace fs = std::filesystem;

nlohmann::json read_json(const fs::path& path) {
  if (!fs::is_regular_file(path)) throw std::runtime_error(path.string() + ": missing (is this a run directory?)");
  try {
    return nlohmann::json::parse(io::read_text_file(path));
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(path.string() + ": invalid JSON: " + e.what());
  }
}

// A number for the table, or "–" when absent.
std::string num(const nlohmann::json& value, int digits = 2) {
  if (!value.is_number()) return "–";
  return fmt::format("{:.{}f}", value.get<double>(), digits);
}

const nlohmann::json& at(const nlohmann::json& j, std::initializer_list<const char*> path) {
  static const nlohmann::json kNull;
  const nlohmann::json* node = &j;
  for (const char* key : path) {
    if (!node->is_object() || !node->contains(key)) return kNull;
    node = &(*node)[key];
  }
  return *node;
}

fs::path plot_script(const std::string& name) {
  for (const fs::path& dir :
       {fs::path(SOFTWRIST_PLOT_SCRIPT_DIR_SOURCE), fs::path(SOFTWRIST_PLOT_SCRIPT_DIR_INSTALLED)}) {
    if (fs::is_regular_file(dir / name)) return dir / name;
  }
  throw std::runtime_error(fmt::format("report: plot script {} not found in {} or {}", name,
                                       SOFTWRIST_PLOT_SCRIPT_DIR_SOURCE, SOFTWRIST_PLOT_SCRIPT_DIR_INSTALLED));
}

// The Python that has Debian's python3-matplotlib: $SOFTWRIST_PYTHON if set, else Debian's /usr/bin/python3
// (a python3 earlier on PATH, such as a pyenv shim, does not see Debian's packages), else python3 on PATH.
std::string python() {
  if (const char* chosen = std::getenv("SOFTWRIST_PYTHON"); chosen != nullptr && *chosen != '\0') return chosen;
  if (fs::exists("/usr/bin/python3")) return "/usr/bin/python3";
  return "python3";
}

}  // namespace

void run_plot_script(const std::string& name, const std::vector<std::string>& args) {
  const fs::path script = plot_script(name);
  std::vector<std::string> command = {python(), script.string()};
  command.insert(command.end(), args.begin(), args.end());
  int code = 0;
  try {
    code = io::run_process(command);
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(
        fmt::format("report: {} (install python3 and python3-matplotlib, or use --no-plots)", e.what()));
  }
  if (code != 0) {
    throw std::runtime_error(
        fmt::format("report: plotting failed ({} exited with {}); is python3-matplotlib installed? (or use --no-plots)",
                    script.string(), code));
  }
}

std::string plot_figures(const fs::path& dir, std::vector<std::string>& files) {
  std::string html;
  for (const auto& plot : read_json(dir / "plots.json")) {
    const std::string file = plot.value("file", "");
    if (!fs::is_regular_file(dir / file)) throw std::runtime_error("report: plot " + file + " was not written");
    files.push_back(file);
    html += fmt::format("<figure><img src=\"{0}\" alt=\"{1}\"><figcaption>{1}</figcaption></figure>\n",
                        html_escape(file), html_escape(plot.value("caption", "")));
  }
  return html;
}

std::string html_escape(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::vector<std::array<std::string, 3>> metric_rows(const std::string& kind, const nlohmann::json& s) {
  std::vector<std::array<std::string, 3>> rows;
  if (kind == "torque_validation") {
    for (const char* method : {"fixed_no_stretch", "fixed_stretch", "motion_capture", "fixed_stretch_selfconsistent"}) {
      const nlohmann::json& label = at(s, {"methods", method});
      rows.push_back({fmt::format("MAE, {} [N m]", html_escape(label.is_string() ? label.get<std::string>() : method)),
                      num(at(s, {"mae_nm", method}), 3), num(at(s, {"paper_mae_nm", method}), 3)});
    }
  } else if (kind == "range_of_motion") {
    for (const auto& m : at(s, {"muscles"})) {
      rows.push_back({fmt::format("{} range [deg]", html_escape(m.value("direction", "?"))),
                      num(m["settled_deg"], 1) + " ± " + num(m["settled_std_deg"], 1) + " (statics " +
                          num(m["analytic_settled_deg"], 1) + ")",
                      num(m["paper_exosuit_deg"], 1) + " ± " + num(m["paper_exosuit_std_deg"], 1) + " (biological " +
                          num(m["paper_biological_deg"], 1) + ")"});
    }
  } else if (kind == "design_optimization") {
    for (const char* p : {"d1", "w1", "d2", "w2"}) {
      rows.push_back({fmt::format("optimum {} [cm]", p), num(at(s, {"optimum_cm", p}), 2),
                      num(at(s, {"paper", "optimum_cm", p}), 2)});
    }
    rows.push_back({"objective, Eqn. objective_function [N m]", num(at(s, {"objective_nm"}), 2), "–"});
    rows.push_back({"minimum pressure meeting the reference [kPa]", num(at(s, {"min_pressure", "pressure_kpa"}), 1),
                    num(at(s, {"paper", "min_pressure_kpa"}), 0)});
    rows.push_back({"d2 at the minimum pressure [cm]", num(at(s, {"min_pressure", "optimum_cm", "d2"}), 2),
                    num(at(s, {"paper", "min_pressure_d2_cm"}), 2)});
  } else if (kind == "tracking") {
    for (const auto& c : at(s, {"controllers"})) {
      const std::string name = html_escape(c.value("controller", "?"));
      for (const char* axis : {"fe", "ur"}) {
        const std::string key = fmt::format("rmse_{}_deg", axis);
        if (!c[key].is_number()) continue;
        rows.push_back({fmt::format("{}: RMSE {}, all (reachable) targets [deg]", name, axis),
                        num(c[key], 2) + " (" + num(c[fmt::format("reachable_rmse_{}_deg", axis)], 2) + ")",
                        num(at(s, {"paper", key.c_str()}), 2)});
      }
      for (const char* direction : {"towards_extension", "towards_flexion"}) {
        if (!c.contains(direction)) continue;
        rows.push_back({fmt::format("{}: step {}, rise time [s] / overshoot [%]", name, direction),
                        num(c[direction]["rise_time_s"], 2) + " / " + num(c[direction]["overshoot_pct"], 1),
                        num(at(s, {"paper", direction, "rise_time_s"}), 2) + " / " +
                            num(at(s, {"paper", direction, "overshoot_pct"}), 0)});
      }
    }
  }
  return rows;
}

std::vector<std::string> summary_lines(const std::string& kind, const nlohmann::json& summary) {
  std::vector<std::string> lines;
  for (const auto& [quantity, simulated, paper] : metric_rows(kind, summary)) {
    // The headline figures: every row but the tracking steps' and the design's secondary ones.
    if (quantity.find(": step ") != std::string::npos || quantity.find("objective") != std::string::npos) continue;
    lines.push_back(paper == "–" || paper.starts_with("– ")
                        ? fmt::format("<b>{}</b>: {}", quantity, simulated)
                        : fmt::format("<b>{}</b>: {} here; {} in the paper", quantity, simulated, paper));
  }
  return lines;
}

namespace {

std::string metrics_section(const std::string& kind, const nlohmann::json& summary) {
  std::string html =
      "<h2>Metrics</h2>\n<div class=\"table-wrap\"><table>\n<tr><th>quantity [unit]</th><th class=\"num\">softwrist"
      "</th><th class=\"num paper\">paper</th></tr>\n";
  for (const auto& row : metric_rows(kind, summary)) {
    html += fmt::format("<tr><td>{}</td><td class=\"num\">{}</td><td class=\"num paper\">{}</td></tr>\n", row[0],
                        row[1], row[2]);
  }
  html += "</table></div>\n";
  if (summary.contains("explanation") && summary["explanation"].is_string()) {
    html += fmt::format("<p>{}</p>\n", html_escape(summary["explanation"]));
  }
  return html;
}

// Renders the run's moments into `out`, appending the files to `files`; empty when the run has none.
std::string renders_section(const fs::path& run_dir, const fs::path& out, std::vector<std::string>& files) {
  const RunMoments run = run_moments(run_dir);
  if (run.moments.empty()) return "";
  std::string html =
      "<h2>Renders</h2>\n<p>Offscreen (OSMesa) renders of the simulated device; each muscle is drawn along its "
      "tendon path, coloured by its pressure from blue (0) to red (the regulator's maximum).</p>\n"
      "<div class=\"renders\">\n";
  PoseRenderer renderer(run.device, 480, 360);
  for (const Moment& moment : run.moments) {
    const std::string file = "render_" + moment.name + ".png";
    write_png(renderer.Render(moment.pose, moment.view), out / file);
    files.push_back(file);
    html += fmt::format("<figure><img src=\"{0}\" alt=\"{1}\"><figcaption>{1} ({2} view)</figcaption></figure>\n",
                        html_escape(file), html_escape(moment.caption), view_name(moment.view));
  }
  html += "</div>\n";
  return html;
}

std::string what_was_run_section(const nlohmann::json& sidecar, const nlohmann::json& config,
                                 const nlohmann::json& summary) {
  std::string html = "<h2>What was run</h2>\n<div class=\"table-wrap\"><table>\n";
  for (const char* key : {"source", "config_hash", "model_hash", "software_version", "cases", "format"}) {
    if (!sidecar.contains(key)) continue;
    const auto& v = sidecar[key];
    html += fmt::format("<tr><th>{}</th><td>{}</td></tr>\n", key,
                        html_escape(v.is_string() ? v.get<std::string>() : v.dump()));
  }
  html += fmt::format("</table></div>\n<h3>Config</h3>\n<pre>{}</pre>\n", html_escape(config.dump(2)));
  html +=
      fmt::format("<details><summary>summary.json</summary><pre>{}</pre></details>\n", html_escape(summary.dump(2)));
  return html;
}

}  // namespace

ReportResult write_report(const fs::path& run_dir, const ReportOptions& options) {
  if (!fs::is_directory(run_dir)) throw std::runtime_error(run_dir.string() + ": not a directory");
  const nlohmann::json sidecar = read_json(run_dir / "trials.json");
  const nlohmann::json summary = read_json(run_dir / "summary.json");
  if (!sidecar.contains("kind") || !sidecar["kind"].is_string()) {
    throw std::runtime_error((run_dir / "trials.json").string() + ": kind: missing");
  }
  const std::string kind = sidecar["kind"];
  const fs::path out = options.out.empty() ? run_dir / "report" : options.out;
  fs::create_directories(out);

  ReportResult result{.page = out / "index.html"};
  std::string figures;
  if (options.plots) {
    run_plot_script("plot_run.py", {run_dir.string(), out.string()});
    figures = plot_figures(out, result.plots);
  }

  const nlohmann::json& config = at(sidecar, {"config"});
  const std::string title = fmt::format("softwrist {}: {}", kind, run_dir.filename().string());
  std::string html = page_head(title, config.is_object() ? config.value("description", "") : "");
  html += summary_box(summary_lines(kind, summary));
  html += metrics_section(kind, summary);
  if (!figures.empty()) html += "<h2>Plots</h2>\n" + figures;
  if (options.renders) html += renders_section(run_dir, out, result.renders);
  html += what_was_run_section(sidecar, config, summary);
  html += page_end();
  write_stylesheet(out);
  std::ofstream(result.page) << html;
  if (!fs::is_regular_file(result.page)) throw std::runtime_error(result.page.string() + ": could not be written");
  return result;
}

}  // namespace softwrist::report
