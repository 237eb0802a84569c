#include "diagnosis/diagnosis_report.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <set>

#include <fmt/format.h>

#include "io/csv.h"
#include "physics/units.h"
#include "report/html_report.h"
#include "report/page_style.h"
#include "sim/device.h"

namespace softwrist::diagnosis {
namespace {

namespace fs = std::filesystem;
using io::format_number;
using report::html_escape;

std::string number_or_empty(double v) { return std::isfinite(v) ? format_number(v) : ""; }

void write_curves(const Diagnosis& d, const fs::path& path) {
  io::CsvWriter csv(path, {"experiment", "kind", "unit", "heldout", "angle_deg", "pressure_kpa", "contraction",
                           "muscle", "channel", "motion", "t_s", "measured", "nominal", "corrected"});
  for (std::size_t t = 0; t < d.prepared.size(); ++t) {
    const PreparedTrial& p = d.prepared[t];
    for (std::size_t i = 0; i < p.points.size(); ++i) {
      const Point& point = p.points[i];
      csv.write_row(
          {p.name, to_string(p.trial->kind), p.unit, point.heldout ? "1" : "0", number_or_empty(point.angle_deg),
           number_or_empty(point.pressure_kpa), number_or_empty(point.contraction),
           point.muscle >= 0 && point.muscle < 4 ? sim::kMuscleNames[static_cast<std::size_t>(point.muscle)] : "",
           std::to_string(point.channel), std::to_string(point.motion), number_or_empty(point.t_s),
           format_number(point.measured), number_or_empty(d.nominal_predictions[t][i]),
           number_or_empty(d.corrected_predictions[t][i])});
    }
  }
}

void write_residual_map(const Diagnosis& d, const fs::path& path) {
  io::CsvWriter csv(path, {"experiment", "angle_deg", "pressure_kpa", "residual", "noise", "significant"});
  for (const auto& e : d.localization) {
    if (std::isfinite(e.angle_deg) && std::isfinite(e.pressure_kpa)) {
      csv.write_row({e.experiment, format_number(e.angle_deg), format_number(e.pressure_kpa), format_number(e.residual),
                     format_number(e.noise), e.significant ? "1" : "0"});
    }
  }
}

std::string effect_rows(const std::vector<EffectFit>& fits) {
  std::string rows;
  for (const auto& f : fits) {
    std::string params;
    for (const auto& [name, value] : f.params) params += fmt::format("{} = {:.4g}<br>", html_escape(name), value);
    if (!f.applicable) {
      rows += fmt::format("<tr><td>{}</td><td colspan=\"5\" class=\"note\">no data it acts on</td></tr>\n",
                          html_escape(f.name));
      continue;
    }
    rows += fmt::format(
        "<tr><td>{}</td><td class=\"num\">{:.3f}</td><td class=\"num\">{:.3f}</td><td class=\"num\">{:.0f}</td>"
        "<td class=\"num\">[{:.0f}, {:.0f}]</td><td>{}</td></tr>\n",
        html_escape(f.name), f.heldout_error_before, f.heldout_error_after, 100 * f.shrink_fraction, 100 * f.ci_low,
        100 * f.ci_high, params);
  }
  return rows;
}

// OUT/corrected/: the nominal model and each rig's placement file with the fitted effects applied, so the next
// simulation, optimization or model-based controller uses what the data taught; and what a placement file cannot
// hold (it acts where the model meets the measurement), to be applied by hand.
nlohmann::json write_corrected_models(const Diagnosis& d, const fs::path& out, const fs::path& dir) {
  nlohmann::json info = {{"files", nlohmann::json::array()}, {"not_in_placement", nlohmann::json::array()}};
  if (!d.corrected) return info;
  fs::create_directories(dir);
  const auto write = [&](const sim::DeviceDescription& device, const std::string& name, const std::string& rig) {
    std::ofstream(dir / name) << sim::device_to_json(device);
    info["files"].push_back({{"rig", rig}, {"file", fs::relative(dir / name, out).generic_string()}});
  };
  write(d.corrected->device, "model.json", "the model given to diagnose (--model)");
  std::set<std::string> names{"model.json"};
  for (const auto& [placement, device] : d.corrected->rigs) {
    std::string name = placement.stem().string() + ".json";
    for (int k = 2; names.contains(name); ++k) name = fmt::format("{}_{}.json", placement.stem().string(), k);
    names.insert(name);
    write(device, name, placement.string());
  }
  const ModelVariant& v = *d.corrected;
  const auto not_held = [&](double value, const std::string& what) {
    if (value != 0.0) info["not_in_placement"].push_back(fmt::format("{} {:.4g}", what, value));
  };
  not_held(v.regulator_dead_time, "regulator dead time [s]");
  not_held(units::rad_to_deg(v.imu_offset_fe), "IMU offset, flexion/extension [deg]");
  not_held(units::rad_to_deg(v.imu_offset_ur), "IMU offset, ulnar/radial [deg]");
  not_held(v.imu_latency, "IMU latency [s]");
  not_held(units::rad_to_deg(v.imu_axis_roll), "IMU axes turned about the forearm [deg]");
  return info;
}

const char* kEffectHeader =
    "<div class=\"table-wrap\"><table><tr><th>effect</th><th class=\"num\">held-out error before [noise units]</th>"
    "<th class=\"num\">after [noise units]</th><th class=\"num\">shrink [%]</th>"
    "<th class=\"num\">95 % bootstrap CI [%]</th><th>fitted</th></tr>\n";

// The result first, every sentence with its numbers: the verdict, how much of the gap the correction closes, and
// which trials keep a gap beyond their noise (and how large) when some do.
std::vector<std::string> summary_lines(const Diagnosis& d) {
  std::vector<std::string> lines = {
      fmt::format("<b>Verdict: {}</b>. {}", html_escape(d.verdict), html_escape(d.reason))};
  const auto gap_trials = std::count_if(d.trials.begin(), d.trials.end(), [](const TrialGap& t) { return t.gap; });
  const std::string overall = fmt::format(
      "Held-out error, the systematic residual in noise units: {:.3f} with the nominal model and {:.3f} "
      "corrected over all {} trials",
      d.heldout_nominal, d.heldout_corrected, d.trials.size());
  // Without a trial that keeps a gap there is nothing to close (a `none`, or an effect named from a pinned tolerance).
  lines.push_back(gap_trials == 0
                      ? overall + "; no trial keeps a gap of its own, so the correction has none to close."
                      : fmt::format("{}; over the {} trials with a gap of their own, {:.3f} and {:.3f}: the "
                                    "correction closes {:.0f} % of it.",
                                    overall, gap_trials, d.gap_nominal, d.gap_corrected, 100.0 * d.gap_closed()));
  std::vector<std::string> remaining;
  for (const TrialGap& t : d.trials) {
    if (!t.remaining_significant) continue;
    remaining.push_back(fmt::format("{} (RMS residual {:.3g} {}, {:.2f} noise units beyond its noise of {:.3g} {}{})",
                                    html_escape(t.experiment), t.rms_corrected, html_escape(t.unit), t.excess_corrected,
                                    t.noise, html_escape(t.unit), t.gap ? "" : "; it had no gap of its own"));
  }
  if (remaining.empty()) {
    lines.push_back("With the corrected model no trial differs from the simulation beyond its noise.");
  } else {
    std::string list;
    for (const std::string& r : remaining) list += (list.empty() ? "" : "; ") + r;
    lines.push_back(fmt::format("A significant gap remains after correction in {} of {} trials: {}.", remaining.size(),
                                d.trials.size(), list));
  }
  return lines;
}

bool attention(const Diagnosis& d) { return d.remaining_gap_significant || d.verdict == "unexplained"; }

std::string effects_section(const Diagnosis& d) {
  return fmt::format(
      "<h2>Effects, each alone on the nominal model (best first)</h2>\n{0}{1}</table></div>\n"
      "<h2>Combination (greedy)</h2>\n{0}{2}</table></div>\n",
      kEffectHeader, effect_rows(d.effects), effect_rows(d.combination));
}

std::string trials_section(const Diagnosis& d) {
  std::string rows;
  for (const auto& t : d.trials) {
    rows += fmt::format(
        "<tr{}><td>{}</td><td>{}</td><td>{}</td><td class=\"num\">{:.3g}</td><td class=\"num\">{:.3g}</td>"
        "<td class=\"num\">{:.3g}</td><td class=\"num\">{:.2f}</td><td class=\"num\">{:.2f}</td>"
        "<td class=\"num\">{:.2g}</td><td>{}</td></tr>\n",
        t.remaining_significant ? " class=\"significant\"" : "", html_escape(t.experiment), to_string(t.kind),
        html_escape(t.unit), t.noise, t.rms_nominal, t.rms_corrected, t.excess_nominal, t.excess_corrected, t.p_value,
        t.remaining_significant ? "yes" : "no");
  }
  return "<h2>Trials</h2>\n<p class=\"note\">Residuals and noise in the trial's unit; the systematic residual in noise "
         "units, sqrt(max(0, mean (r/&sigma;)<sup>2</sup> &minus; 1)). A red edge marks a trial that keeps a gap "
         "beyond its noise after correction.</p>\n<div class=\"table-wrap\"><table><tr><th>trial</th><th>kind</th>"
         "<th>unit</th><th class=\"num\">noise</th><th class=\"num\">RMS residual, nominal</th>"
         "<th class=\"num\">RMS residual, corrected</th><th class=\"num\">systematic, nominal [noise units]</th>"
         "<th class=\"num\">systematic, corrected [noise units]</th><th class=\"num\">p (nominal gap is noise)</th>"
         "<th>gap remains after correction</th></tr>\n" +
         rows + "</table></div>\n";
}

std::string where_section(const Diagnosis& d) {
  std::string rows;
  int shown = 0;
  for (const auto& e : d.localization) {
    if (++shown > 25) break;
    rows += fmt::format(
        "<tr{}><td>{}</td><td>{}</td><td>{}</td><td class=\"num\">{:.4g}</td><td class=\"num\">{:.4g}</td>"
        "<td>{}</td><td class=\"num\">{:.2g}</td></tr>\n",
        e.significant ? " class=\"located\"" : "", html_escape(e.experiment), html_escape(e.where), html_escape(e.unit),
        e.residual, e.noise, e.significant ? "yes" : "no", e.p_value);
  }
  return "<h2>Where the gap lies, with the nominal model (most significant first)</h2>\n"
         "<p class=\"note\">An amber edge marks a part whose residual is significant.</p>\n"
         "<div class=\"table-wrap\"><table><tr><th>trial</th><th>where</th><th>unit</th>"
         "<th class=\"num\">systematic residual</th><th class=\"num\">noise alone would give</th><th>significant</th>"
         "<th class=\"num\">p</th></tr>\n" +
         rows + "</table></div>\n";
}

std::string skipped_section(const Diagnosis& d) {
  std::string items;
  for (const auto& p : d.problems)
    items += fmt::format("<li>{}: {}</li>\n", html_escape(p.file), html_escape(p.reason));
  return "<h2>Skipped</h2>\n<ul>" + (items.empty() ? std::string("<li>none</li>") : items) + "</ul>\n";
}

}  // namespace

DiagnosisReport write_diagnosis_report(const Diagnosis& d, const fs::path& out, const DiagnosisReportOptions& options) {
  fs::create_directories(out);
  DiagnosisReport result{.json = out / "diagnosis.json", .page = out / "diagnosis.html"};
  nlohmann::json json = to_json(d);
  json["wall_s"] = options.wall_s;
  json["corrected_models"] = write_corrected_models(d, out, out / "corrected");
  std::ofstream(result.json) << json.dump(2) << "\n";
  write_curves(d, out / "curves.csv");
  write_residual_map(d, out / "residual_map.csv");
  std::string figures;
  if (options.plots) {
    report::run_plot_script("plot_diagnosis.py", {out.string()});
    figures = report::plot_figures(out, result.plots);
  }
  if (figures.empty()) figures = "<p class=\"note\">(no plots)</p>\n";

  std::ofstream page(result.page);
  page << report::page_head("Sim-to-real gap diagnosis", "") << report::summary_box(summary_lines(d), attention(d))
       << effects_section(d) << trials_section(d) << where_section(d) << "<h2>Plots</h2>\n"
       << figures << skipped_section(d) << report::page_end();
  report::write_stylesheet(out);
  return result;
}

}  // namespace softwrist::diagnosis
