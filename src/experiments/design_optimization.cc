#include "experiments/design_optimization.h"

#include <chrono>

#include <fmt/format.h>

#include "io/csv.h"
#include "io/text_file.h"
#include "optimize/personalize.h"
#include "physics/exosuit_layout.h"
#include "physics/paper_parameters.h"
#include "physics/units.h"

namespace softwrist::experiments {
namespace {

using io::format_number;
using physics::Placement;
using units::cm_to_m;
using units::m_to_cm;

Placement read_placement_cm(io::JsonReader reader) {
  Placement p{.d1 = cm_to_m(reader.number("d1")),
              .w1 = cm_to_m(reader.number("w1")),
              .d2 = cm_to_m(reader.number("d2")),
              .w2 = cm_to_m(reader.number("w2"))};
  reader.finish();
  return p;
}

nlohmann::json placement_cm_json(const Placement& p) {
  return {{"d1", m_to_cm(p.d1)}, {"w1", m_to_cm(p.w1)}, {"d2", m_to_cm(p.d2)}, {"w2", m_to_cm(p.w2)}};
}

}  // namespace

DesignSettings read_design_settings(io::JsonReader& reader, const ExperimentConfig& config) {
  DesignSettings s;
  const std::filesystem::path reference = config_path(reader, "reference", config);
  s.reference_text = io::read_text_file(reference);
  const int samples = static_cast<int>(reader.integer("samples", 140));
  if (samples < 2 || samples > 100000) reader.fail("samples", "must be 2..100000");
  s.problem.samples = optimize::resample(optimize::read_reference_torque(reference), samples);
  s.problem.pressure = units::kpa_to_pa(reader.positive("pressure_kpa", physics::kRegulatorMaxPressureKpa));
  s.problem.fpam =
      reader.has("fpam") ? optimize::read_design_fpam(reader.child("fpam")) : physics::paper::design_fpam();
  s.problem.wrist_radius = cm_to_m(reader.positive("wrist_radius_cm", 2.0));
  s.problem.max_stretch_angle = units::deg_to_rad(reader.number("max_stretch_angle_deg"));
  if (reader.has("bounds_cm")) {
    io::JsonReader bounds = reader.child("bounds_cm");
    s.problem.bounds = {read_placement_cm(bounds.child("lower")), read_placement_cm(bounds.child("upper"))};
    bounds.finish();
  }
  if (reader.has("start_resolution_cm"))
    s.options.start_resolution = read_placement_cm(reader.child("start_resolution_cm"));
  s.options.algorithm = reader.text("algorithm", "neldermead");
  const std::string objective = reader.text("objective", "deficit");
  if (objective == "deficit") {
    s.problem.objective = optimize::DesignObjective::kDeficit;
  } else if (objective == "absolute_error") {
    s.problem.objective = optimize::DesignObjective::kAbsoluteError;
  } else {
    reader.fail("objective", fmt::format("'{}' is not deficit or absolute_error", objective));
  }
  if (reader.has("pressure_search")) {
    io::JsonReader search = reader.child("pressure_search");
    optimize::PressureSearch p;
    p.low = s.problem.pressure;
    p.high = units::kpa_to_pa(search.positive("max_kpa", 600.0));
    p.tolerance = units::kpa_to_pa(search.positive("tolerance_kpa", 0.5));
    p.screened_starts = static_cast<int>(search.integer("screened_starts", 16));
    if (p.screened_starts < 1) search.fail("screened_starts", "must be >= 1");
    if (!(p.high > p.low)) search.fail("max_kpa", "must be above pressure_kpa");
    search.finish();
    s.pressure_search = p;
  }
  if (reader.has("exhaustive_check_resolution_cm")) {
    const double r = cm_to_m(reader.positive("exhaustive_check_resolution_cm", 0.25));
    s.exhaustive_resolution = Placement{.d1 = r, .w1 = r, .d2 = r, .w2 = r};
  }
  try {
    optimize::validate(s.problem);
    optimize::validate(s.options);
  } catch (const physics::InvalidParameter& e) {
    reader.fail("", e.what());
  }
  return s;
}

std::unique_ptr<DesignOptimization> DesignOptimization::Create(const ExperimentConfig& config, io::JsonReader& reader) {
  auto e = std::unique_ptr<DesignOptimization>(new DesignOptimization());
  e->settings_ = read_design_settings(reader, config);
  e->starts_ = optimize::start_grid(e->settings_.problem.bounds, e->settings_.options.start_resolution);
  return e;
}

std::string DesignOptimization::model_hash() const { return content_hash(settings_.reference_text); }

std::vector<Column> DesignOptimization::columns() const {
  return {{"start_d1_cm", "cm", "initial guess"},
          {"start_w1_cm", "cm", ""},
          {"start_d2_cm", "cm", ""},
          {"start_w2_cm", "cm", ""},
          {"d1_cm", "cm", "local optimum"},
          {"w1_cm", "cm", ""},
          {"d2_cm", "cm", ""},
          {"w2_cm", "cm", ""},
          {"objective_nm", "N m", "Eqn. objective_function at the optimum"},
          {"evaluations", "", "objective evaluations of this start"}};
}

std::vector<Row> DesignOptimization::run_case(int index) const {
  const auto& start = starts_[static_cast<std::size_t>(index)];
  const auto solution =
      optimize::optimize_from(settings_.problem, start, settings_.options, settings_.problem.pressure);
  const auto& p = solution.placement;
  return {{format_number(m_to_cm(start.d1)), format_number(m_to_cm(start.w1)), format_number(m_to_cm(start.d2)),
           format_number(m_to_cm(start.w2)), format_number(m_to_cm(p.d1)), format_number(m_to_cm(p.w1)),
           format_number(m_to_cm(p.d2)), format_number(m_to_cm(p.w2)), format_number(solution.objective),
           std::to_string(solution.evaluations)}};
}

nlohmann::json DesignOptimization::summarize(const io::CsvTable& log, const std::filesystem::path& run_dir) const {
  const auto& problem = settings_.problem;
  std::vector<optimize::LocalSolution> solutions;
  const int c_objective = log.column("objective_nm"), c_evaluations = log.column("evaluations");
  const std::array<int, 4> c_p = {log.column("d1_cm"), log.column("w1_cm"), log.column("d2_cm"), log.column("w2_cm")};
  for (std::size_t row = 0; row < log.row_count(); ++row) {
    solutions.push_back({.placement = {cm_to_m(log.number(row, c_p[0])), cm_to_m(log.number(row, c_p[1])),
                                       cm_to_m(log.number(row, c_p[2])), cm_to_m(log.number(row, c_p[3]))},
                         .objective = log.number(row, c_objective),
                         .evaluations = log.integer(row, c_evaluations)});
  }
  const optimize::DesignResult result = optimize::best_of(solutions);
  const optimize::DesignEvaluator evaluator(problem);
  const physics::Muscle muscle = optimize::design_muscle(problem, result.best.placement);
  nlohmann::json summary = {{"optimum_cm", placement_cm_json(result.best.placement)},
                            {"objective_nm", result.best.objective},
                            {"mean_deficit_nm", result.best.objective / problem.samples.angles.size()},
                            {"max_deficit_nm", evaluator.max_deficit(result.best.placement)},
                            {"rest_length_cm", m_to_cm(muscle.rest_length)},
                            {"starts", result.starts},
                            {"evaluations", result.evaluations},
                            {"pressure_kpa", units::pa_to_kpa(problem.pressure)},
                            {"paper",
                             {{"optimum_cm", placement_cm_json(physics::paper::kOptimizedPlacement)},
                              {"min_pressure_kpa", 312.0},
                              {"min_pressure_d2_cm", 3.14}}}};
  // The starts that reached the best objective (to 1e-9 N m): how often the multi-start finds it.
  int at_best = 0;
  for (const auto& s : solutions) at_best += s.objective <= result.best.objective + 1e-9;
  summary["starts_reaching_optimum"] = at_best;

  std::vector<double> min_pressure_curve;
  if (settings_.pressure_search) {
    const auto pressure = optimize::minimum_pressure(problem, settings_.options, *settings_.pressure_search);
    nlohmann::json trace = nlohmann::json::array();
    for (const auto& [p, deficit] : pressure.trace)
      trace.push_back({{"pressure_kpa", units::pa_to_kpa(p)}, {"max_deficit_nm", deficit}});
    summary["min_pressure"] = {{"found", pressure.found}, {"trace", trace}};
    if (pressure.found) {
      summary["min_pressure"]["pressure_kpa"] = units::pa_to_kpa(pressure.pressure);
      summary["min_pressure"]["optimum_cm"] = placement_cm_json(pressure.design.placement);
      min_pressure_curve =
          optimize::DesignEvaluator(problem, pressure.pressure).torque_curve(pressure.design.placement);
    }
  }
  if (settings_.exhaustive_resolution) {
    const auto check = optimize::exhaustive_search(problem, *settings_.exhaustive_resolution, settings_.options.jobs);
    summary["exhaustive_check"] = {{"resolution_cm", m_to_cm(settings_.exhaustive_resolution->d1)},
                                   {"points", check.evaluations},
                                   {"best_cm", placement_cm_json(check.placement)},
                                   {"objective_nm", check.objective},
                                   {"multistart_not_worse", result.best.objective <= check.objective + 1e-9}};
  }
  io::CsvWriter curve(run_dir / "design_curve.csv",
                      {"angle_deg", "reference_nm", "optimized_nm", "min_pressure_optimized_nm"});
  const std::vector<double> optimized = evaluator.torque_curve(result.best.placement);
  for (std::size_t i = 0; i < optimized.size(); ++i) {
    curve.write_row({format_number(units::rad_to_deg(problem.samples.angles[i])),
                     format_number(problem.samples.torques[i]), format_number(optimized[i]),
                     min_pressure_curve.empty() ? "" : format_number(min_pressure_curve[i])});
  }
  summary["files"] = {{"design_curve", "design_curve.csv"}};
  return summary;
}

}  // namespace softwrist::experiments
