#include "report/html_report.h"

#include <array>
#include <cstdlib>
#include <fstream>
#include <stdexcept>

#include <fmt/format.h>

#include "io/subprocess.h"
#include "io/text_file.h"
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
std::string num(const nlohmann::json& value, int digits = 2, const std::string& unit = "") {
  if (!value.is_number()) return "–";
  return fmt::format("{:.{}f}{}", value.get<double>(), digits, unit);
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
      rows.push_back({fmt::format("MAE, {}", html_escape(at(s, {"methods", method}).is_string()
                                                             ? at(s, {"methods", method}).get<std::string>()
                                                             : method)),
                      num(at(s, {"mae_nm", method}), 3, " N m"), num(at(s, {"paper_mae_nm", method}), 3, " N m")});
    }
  } else if (kind == "range_of_motion") {
    for (const auto& m : at(s, {"muscles"})) {
      rows.push_back({fmt::format("{} range", html_escape(m.value("direction", "?"))),
                      num(m["settled_deg"], 1, "°") + " ± " + num(m["settled_std_deg"], 1, "°") + " (statics " +
                          num(m["analytic_settled_deg"], 1, "°") + ")",
                      num(m["paper_exosuit_deg"], 1, "°") + " ± " + num(m["paper_exosuit_std_deg"], 1, "°") +
                          " (biological " + num(m["paper_biological_deg"], 1, "°") + ")"});
    }
  } else if (kind == "design_optimization") {
    for (const char* p : {"d1", "w1", "d2", "w2"}) {
      rows.push_back({fmt::format("optimum {}", p), num(at(s, {"optimum_cm", p}), 2, " cm"),
                      num(at(s, {"paper", "optimum_cm", p}), 2, " cm")});
    }
    rows.push_back({"objective (Eqn. objective_function)", num(at(s, {"objective_nm"}), 2, " N m"), "–"});
    rows.push_back({"minimum pressure meeting the reference", num(at(s, {"min_pressure", "pressure_kpa"}), 1, " kPa"),
                    num(at(s, {"paper", "min_pressure_kpa"}), 0, " kPa")});
    rows.push_back({"d2 at the minimum pressure", num(at(s, {"min_pressure", "optimum_cm", "d2"}), 2, " cm"),
                    num(at(s, {"paper", "min_pressure_d2_cm"}), 2, " cm")});
  } else if (kind == "tracking") {
    for (const auto& c : at(s, {"controllers"})) {
      const std::string name = html_escape(c.value("controller", "?"));
      for (const char* axis : {"fe", "ur"}) {
        const std::string key = fmt::format("rmse_{}_deg", axis);
        if (!c[key].is_number()) continue;
        rows.push_back({fmt::format("{}: RMSE {} (reachable targets)", name, axis),
                        num(c[key], 2, "°") + " (" + num(c[fmt::format("reachable_rmse_{}_deg", axis)], 2, "°") + ")",
                        num(at(s, {"paper", key.c_str()}), 2, "°")});
      }
      for (const char* direction : {"towards_extension", "towards_flexion"}) {
        if (!c.contains(direction)) continue;
        rows.push_back({fmt::format("{}: step {} rise time / overshoot", name, direction),
                        num(c[direction]["rise_time_s"], 2, " s") + " / " + num(c[direction]["overshoot_pct"], 1, " %"),
                        num(at(s, {"paper", direction, "rise_time_s"}), 2, " s") + " / " +
                            num(at(s, {"paper", direction, "overshoot_pct"}), 0, " %")});
      }
    }
  }
  return rows;
}

namespace {

std::string page_head(const std::string& title, const nlohmann::json& config) {
  return fmt::format(R"(<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>{0}</title>
<style>
body {{ font-family: sans-serif; max-width: 1000px; margin: 2em auto; color: #222; }}
table {{ border-collapse: collapse; margin: 1em 0; }} td, th {{ border: 1px solid #ccc; padding: 4px 10px; text-align: left; }}
th {{ background: #f0f0f0; }} figure {{ margin: 1.5em 0; }} img {{ max-width: 100%; }}
figcaption {{ color: #555; font-size: 0.9em; }} .missing {{ color: #b00; font-weight: bold; }}
.renders {{ display: grid; grid-template-columns: 1fr 1fr; gap: 0 1.5em; }} pre {{ background: #f7f7f7; padding: 1em; overflow-x: auto; }}
</style></head><body>
<h1>{0}</h1>
<p>{1}</p>
)",
                     html_escape(title), html_escape(config.is_object() ? config.value("description", "") : ""));
}

std::string metrics_section(const std::string& kind, const nlohmann::json& summary) {
  std::string html = "<h2>Metrics</h2>\n<table><tr><th>quantity</th><th>softwrist</th><th>paper</th></tr>\n";
  for (const auto& row : metric_rows(kind, summary)) {
    html += fmt::format("<tr><td>{}</td><td>{}</td><td>{}</td></tr>\n", row[0], row[1], row[2]);
  }
  html += "</table>\n";
  if (summary.contains("explanation") && summary["explanation"].is_string()) {
    html += fmt::format("<p>{}</p>\n", html_escape(summary["explanation"]));
  }
  return html;
}

// The figures plot_run.py listed in plots.json; each file must exist in `out`. Appends the files to `files`.
std::string plots_section(const nlohmann::json& plots, const fs::path& out, std::vector<std::string>& files) {
  std::string html;
  if (!plots.empty()) html += "<h2>Plots</h2>\n";
  for (const auto& plot : plots) {
    const std::string file = plot.value("file", "");
    if (!fs::is_regular_file(out / file)) throw std::runtime_error("report: plot " + file + " was not written");
    files.push_back(file);
    html += fmt::format("<figure><img src=\"{0}\" alt=\"{1}\"><figcaption>{1}</figcaption></figure>\n",
                        html_escape(file), html_escape(plot.value("caption", "")));
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
  std::string html = "<h2>What was run</h2>\n<table>\n";
  for (const char* key : {"source", "config_hash", "model_hash", "software_version", "cases", "format"}) {
    if (!sidecar.contains(key)) continue;
    const auto& v = sidecar[key];
    html += fmt::format("<tr><th>{}</th><td>{}</td></tr>\n", key,
                        html_escape(v.is_string() ? v.get<std::string>() : v.dump()));
  }
  html += fmt::format("</table>\n<h3>Config</h3>\n<pre>{}</pre>\n", html_escape(config.dump(2)));
  html +=
      fmt::format("<details><summary>summary.json</summary><pre>{}</pre></details>\n", html_escape(summary.dump(2)));
  return html;
}

// A plot or render that did not load says so on the page (a moved page without its PNGs, say); the count of
// loaded images is on <body data-images> for the headless-browser test.
constexpr const char* kPageEnd = R"(<script>
window.addEventListener("load", () => {
  const images = Array.from(document.images);
  const missing = images.filter((img) => !img.complete || img.naturalWidth === 0);
  for (const img of missing) {
    const note = document.createElement("p");
    note.className = "missing";
    note.textContent = "image missing: " + img.getAttribute("src");
    img.replaceWith(note);
  }
  document.body.dataset.images = (images.length - missing.length) + "/" + images.length;
});
</script>
</body></html>
)";

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
  nlohmann::json plots = nlohmann::json::array();
  if (options.plots) {
    run_plot_script("plot_run.py", {run_dir.string(), out.string()});
    plots = read_json(out / "plots.json");
  }

  const nlohmann::json& config = at(sidecar, {"config"});
  const std::string title = fmt::format("softwrist {}: {}", kind, run_dir.filename().string());
  std::string html = page_head(title, config);
  html += metrics_section(kind, summary);
  html += plots_section(plots, out, result.plots);
  if (options.renders) html += renders_section(run_dir, out, result.renders);
  html += what_was_run_section(sidecar, config, summary);
  html += kPageEnd;
  std::ofstream(result.page) << html;
  if (!fs::is_regular_file(result.page)) throw std::runtime_error(result.page.string() + ": could not be written");
  return result;
}

}  // namespace softwrist::report
