#include "diagnosis/diagnosis_report.h"

#include <cmath>
#include <fstream>
#include <set>

#include <fmt/format.h>

#include "io/csv.h"
#include "physics/units.h"
#include "report/html_report.h"
#include "sim/device.h"

namespace softwrist::diagnosis {
namespace {

namespace fs = std::filesystem;
using io::format_number;
using report::html_escape;

std::string number_or_empty(double v) { return std::isfinite(v) ? format_number(v) : ""; }

void write_curves(const Diagnosis& d, const fs::path& path) {
  io::CsvWriter csv(path, {"experiment", "kind", "unit", "heldout", "angle_deg", "pressure_kpa", "contraction",
                           "channel", "motion", "t_s", "measured", "nominal", "corrected"});
  for (std::size_t t = 0; t < d.prepared.size(); ++t) {
    const PreparedTrial& p = d.prepared[t];
    for (std::size_t i = 0; i < p.points.size(); ++i) {
      const Point& point = p.points[i];
      csv.write_row({p.name, to_string(p.trial->kind), p.unit, point.heldout ? "1" : "0",
                     number_or_empty(point.angle_deg), number_or_empty(point.pressure_kpa),
                     number_or_empty(point.contraction), std::to_string(point.channel), std::to_string(point.motion),
                     number_or_empty(point.t_s), format_number(point.measured),
                     number_or_empty(d.nominal_predictions[t][i]), number_or_empty(d.corrected_predictions[t][i])});
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
      rows += fmt::format("<tr><td>{}</td><td colspan=5>no data it acts on</td></tr>\n", html_escape(f.name));
      continue;
    }
    rows += fmt::format(
        "<tr><td>{}</td><td>{:.3f}</td><td>{:.3f}</td><td>{:.0f} %</td><td>[{:.0f}, {:.0f}] %</td><td>{}</td></tr>\n",
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
  return info;
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
  if (options.plots) {
    report::run_plot_script("plot_diagnosis.py", {out.string()});
    for (const auto& entry : fs::directory_iterator(out)) {
      if (entry.path().extension() == ".png") result.plots.push_back(entry.path().filename().string());
    }
    std::sort(result.plots.begin(), result.plots.end());
  }

  std::string trials;
  for (const auto& t : d.trials) {
    trials += fmt::format(
        "<tr><td>{}</td><td>{}</td><td>{:.4g} {}</td><td>{:.4g}</td><td>{:.4g}</td><td>{:.2g}{}</td></tr>\n",
        html_escape(t.experiment), to_string(t.kind), t.noise, html_escape(t.unit), t.rms_nominal, t.rms_corrected,
        t.p_value, t.significant ? " (significant)" : "");
  }
  std::string where;
  int shown = 0;
  for (const auto& e : d.localization) {
    if (++shown > 25) break;
    where += fmt::format("<tr><td>{}</td><td>{}</td><td>{:.4g}</td><td>{:.4g}</td><td>{} {:.2g}</td></tr>\n",
                         html_escape(e.experiment), html_escape(e.where), e.residual, e.noise,
                         e.significant ? "yes," : "no,", e.p_value);
  }
  std::string skipped;
  for (const auto& p : d.problems)
    skipped += fmt::format("<li>{}: {}</li>\n", html_escape(p.file), html_escape(p.reason));
  std::string images;
  for (const auto& plot : result.plots)
    images += fmt::format("<figure><img src=\"{}\" alt=\"{}\"></figure>\n", plot, plot);

  std::ofstream page(result.page);
  page << fmt::format(R"(<!DOCTYPE html>
<html><head><meta charset="utf-8"><title>softwrist gap diagnosis</title>
<style>body{{font-family:sans-serif;max-width:1100px;margin:auto}} table{{border-collapse:collapse}}
td,th{{border:1px solid #ccc;padding:3px 6px;font-size:13px}} img{{max-width:100%}}</style></head><body>
<h1>Sim-to-real gap diagnosis</h1>
<p><b>Verdict: {}</b> ({})</p>
<p>Held-out error ({}): nominal {:.3f}, corrected {:.3f}; over the trials with a significant gap {:.3f} and {:.3f}
(closed {:.1f} %); a significant gap remains after correction: {}.</p>
<h2>Effects, each alone on the nominal model (best first)</h2>
<table><tr><th>effect</th><th>held-out before</th><th>after</th><th>shrink</th><th>95 % bootstrap CI</th><th>fitted</th></tr>
{}</table>
<h2>Combination (greedy)</h2>
<table><tr><th>effect</th><th>held-out before</th><th>after</th><th>shrink</th><th>95 % bootstrap CI</th><th>fitted</th></tr>
{}</table>
<h2>Trials</h2>
<table><tr><th>trial</th><th>kind</th><th>noise</th><th>RMS residual, nominal</th><th>corrected</th><th>p (nominal gap is noise)</th></tr>
{}</table>
<h2>Where the gap lies (most significant first)</h2>
<table><tr><th>trial</th><th>where</th><th>residual</th><th>noise alone</th><th>significant, p</th></tr>
{}</table>
<h2>Plots</h2>
{}
<h2>Skipped</h2><ul>{}</ul>
</body></html>
)",
                      html_escape(d.verdict), html_escape(d.reason), kErrorMetric, d.heldout_nominal,
                      d.heldout_corrected, d.gap_nominal, d.gap_corrected, 100.0 * d.gap_closed(),
                      d.remaining_gap_significant ? "yes" : "no", effect_rows(d.effects), effect_rows(d.combination),
                      trials, where, images.empty() ? "<p>(no plots)</p>" : images,
                      skipped.empty() ? "<li>none</li>" : skipped);
  return result;
}

}  // namespace softwrist::diagnosis
