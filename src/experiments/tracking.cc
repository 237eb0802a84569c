#include "experiments/tracking.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include <fmt/format.h>

#include "control/excitation_controller.h"
#include "control/model_based_controller.h"
#include "control/paper_controller.h"
#include "control/tracking_metrics.h"
#include "io/csv.h"
#include "physics/units.h"
#include "sim/wrist_statics.h"

namespace softwrist::experiments {
namespace {

using io::format_number;

// Section Planar angle tracking: 0.84 s and 19 % towards extension ("increasing" in the paper, which counts
// extension positive there), 0.54 s and 44 % towards flexion; Section Spatial trajectory tracking: 5.18 and 7.12 deg.
const nlohmann::json kPaperFigures = {{"towards_extension", {{"rise_time_s", 0.84}, {"overshoot_pct", 19.0}}},
                                      {"towards_flexion", {{"rise_time_s", 0.54}, {"overshoot_pct", 44.0}}},
                                      {"rmse_fe_deg", 5.18},
                                      {"rmse_ur_deg", 7.12}};

control::PaperControllerParameters read_paper_parameters(io::JsonReader& r, double max_kpa) {
  control::PaperControllerParameters p;
  p.period_s = r.positive("period_s", p.period_s);
  p.gain_kpa_per_deg = r.non_negative("gain_kpa_per_deg", p.gain_kpa_per_deg);
  p.initial_kpa = r.non_negative("initial_kpa", p.initial_kpa);
  p.release_factor = r.number("release_factor", p.release_factor);
  if (p.release_factor < 1.0) r.fail("release_factor", "must be >= 1");
  if (p.initial_kpa > max_kpa) r.fail("initial_kpa", fmt::format("is above the regulator's {} kPa", max_kpa));
  p.max_kpa = max_kpa;
  return p;
}

control::ModelBasedParameters read_model_based_parameters(io::JsonReader& r, double max_kpa) {
  control::ModelBasedParameters p;
  p.period_s = r.positive("period_s", p.period_s);
  p.co_contraction_kpa = r.non_negative("co_contraction_kpa", p.co_contraction_kpa);
  if (p.co_contraction_kpa >= max_kpa) r.fail("co_contraction_kpa", "must be below the regulator's maximum");
  p.reference_bandwidth_rad_s = r.positive("reference_bandwidth_rad_s", p.reference_bandwidth_rad_s);
  p.kp_nm_per_rad = r.non_negative("kp_nm_per_rad", p.kp_nm_per_rad);
  p.ki_nm_per_rad_s = r.non_negative("ki_nm_per_rad_s", p.ki_nm_per_rad_s);
  p.kd_nms_per_rad = r.non_negative("kd_nms_per_rad", p.kd_nms_per_rad);
  p.integral_limit_nm = r.non_negative("integral_limit_nm", p.integral_limit_nm);
  p.velocity_cutoff_hz = r.positive("velocity_cutoff_hz", p.velocity_cutoff_hz);
  p.lead_s = r.non_negative("lead_s", p.lead_s);
  p.reach_margin_deg = r.non_negative("reach_margin_deg", p.reach_margin_deg);
  p.max_kpa = max_kpa;
  return p;
}

control::ExcitationRoutineParameters read_excitation_parameters(io::JsonReader& r, double max_kpa) {
  control::ExcitationRoutineParameters p;
  if (r.has("step_levels_kpa")) p.step_levels_kpa = r.numbers("step_levels_kpa");
  if (p.step_levels_kpa.empty()) r.fail("step_levels_kpa", "must list at least one pressure");
  for (double level : p.step_levels_kpa) {
    if (!(level > 0.0 && level <= max_kpa)) {
      r.fail("step_levels_kpa", fmt::format("{} kPa is outside 0..{} kPa", level, max_kpa));
    }
  }
  p.hold_s = r.positive("hold_s", p.hold_s);
  p.ramp_s = r.positive("ramp_s", p.ramp_s);
  p.co_contraction_kpa = r.non_negative("co_contraction_kpa", p.co_contraction_kpa);
  p.start_rest_s = r.non_negative("start_rest_s", p.start_rest_s);
  p.edge_rate_kpa_s = r.positive("edge_rate_kpa_s", p.edge_rate_kpa_s);
  if (p.co_contraction_kpa > max_kpa) r.fail("co_contraction_kpa", fmt::format("is above {} kPa", max_kpa));
  return p;
}

std::unique_ptr<control::Trajectory> read_trajectory(io::JsonReader& r) {
  const std::string type = r.text("type");
  if (type == "steps") {
    std::vector<control::WristAngles> levels;
    for (double fe : r.numbers("levels_fe_deg")) levels.push_back({.fe_deg = fe, .ur_deg = 0.0});
    return std::make_unique<control::StepTrajectory>(std::move(levels), r.positive("hold_s", 10.0));
  }
  if (type == "sinusoid") {
    control::SinusoidParameters p;
    p.fe_min_deg = r.number("fe_min_deg", p.fe_min_deg);
    p.fe_max_deg = r.number("fe_max_deg", p.fe_max_deg);
    p.ur_min_deg = r.number("ur_min_deg", p.ur_min_deg);
    p.ur_max_deg = r.number("ur_max_deg", p.ur_max_deg);
    if (p.fe_min_deg > p.fe_max_deg) r.fail("fe_min_deg", "is above fe_max_deg");
    if (p.ur_min_deg > p.ur_max_deg) r.fail("ur_min_deg", "is above ur_max_deg");
    p.period_s = r.positive("period_s", p.period_s);
    p.phase_lag_deg = r.number("phase_lag_deg", p.phase_lag_deg);
    p.periods = r.positive("periods", p.periods);
    return std::make_unique<control::SinusoidTrajectory>(p);
  }
  r.fail("type", fmt::format("'{}' is not steps or sinusoid", type));
}

// Which pairs the controllers drive: "fe", "ur" or both.
control::AxisFlags read_active_pairs(io::JsonReader& r) {
  if (!r.has("pairs")) return {true, true};
  const nlohmann::json& list = r.raw("pairs");
  control::AxisFlags active{false, false};
  if (!list.is_array() || list.empty()) r.fail("pairs", "must be a non-empty list of \"fe\" and \"ur\"");
  for (const auto& item : list) {
    if (item == "fe")
      active[0] = true;
    else if (item == "ur")
      active[1] = true;
    else
      r.fail("pairs", fmt::format("{} is not \"fe\" or \"ur\"", item.dump()));
  }
  return active;
}

}  // namespace

bool set_controller_model(nlohmann::json& config, const std::filesystem::path& placement) {
  bool found = false;
  if (!config.contains("controllers") || !config["controllers"].is_array()) return false;
  for (nlohmann::json& c : config["controllers"]) {
    if (c.is_object() && c.value("name", "") == "model_based") {
      c["model"] = placement.string();
      found = true;
    }
  }
  return found;
}

void Tracking::read_controllers(io::JsonReader& reader, const ExperimentConfig& config, double max_kpa) {
  const nlohmann::json& list = reader.raw("controllers");
  if (!list.is_array() || list.empty()) reader.fail("controllers", "must be a non-empty list of controllers");
  for (std::size_t i = 0; i < list.size(); ++i) {
    io::JsonReader c(list[i], reader.source(), fmt::format("controllers[{}]", i));
    const std::string name = c.text("name");
    if (name == "paper") {
      const auto p = read_paper_parameters(c, max_kpa);
      controllers_.push_back({name, [p] { return std::make_unique<control::PaperController>(p); }});
    } else if (name == "model_based") {
      // The controller's own model of the device: by default the simulated one; another placement file tests how
      // the controller copes with a model that is off.
      const sim::DeviceDescription own =
          c.has("model") ? sim::load_device(config_path(c, "model", config)) : device_->description;
      const physics::WristModel wrist = sim::wrist_model(own, gravity_);
      control::ModelBasedParameters p = read_model_based_parameters(c, max_kpa);
      // The feedforward looks ahead by the regulators' lag: the model's time constant unless the config says.
      if (!c.has("lead_s")) p.lead_s = own.regulator.time_constant;
      controllers_.push_back({name, [wrist, p] { return std::make_unique<control::ModelBasedController>(wrist, p); }});
    } else if (name == "excitation") {
      if (list.size() != 1) c.fail("name", "the excitation routine runs alone (it is not tracking)");
      excitation_ = control::excitation_routine(read_excitation_parameters(c, max_kpa), max_kpa);
      const std::vector<control::ExcitationSegment> segments = excitation_;
      controllers_.push_back(
          {name, [segments, max_kpa] { return std::make_unique<control::ExcitationController>(segments, max_kpa); }});
    } else {
      c.fail("name", fmt::format("'{}' is not paper, model_based or excitation", name));
    }
    c.finish();
    for (std::size_t j = 0; j + 1 < controllers_.size(); ++j) {
      if (controllers_[j].name == name) c.fail("name", fmt::format("'{}' is listed twice", name));
    }
  }
}

std::unique_ptr<Tracking> Tracking::Create(const ExperimentConfig& config, io::JsonReader& reader) {
  auto e = std::unique_ptr<Tracking>(new Tracking());
  e->gravity_ = reader.boolean("hand_supported", false) ? 0.0 : sim::kStandardGravity;
  e->device_ = std::make_unique<SimulatedDevice>(config_path(reader, "model", config),
                                                 sim::ModelOptions{.gravity = e->gravity_});
  const double max_kpa = units::pa_to_kpa(e->device_->description.regulator.max_pressure);
  e->options_.active_axes = read_active_pairs(reader);
  e->settle_s_ = reader.non_negative("settle_s", 3.0);
  if (reader.has("imu")) {
    io::JsonReader imu = reader.child("imu");
    e->imu_.period_s = imu.positive("period_s", e->imu_.period_s);
    e->imu_.noise_std_deg = imu.non_negative("noise_std_deg", e->imu_.noise_std_deg);
    e->imu_.bias_limit_deg = imu.non_negative("bias_limit_deg", e->imu_.bias_limit_deg);
    imu.finish();
  }
  if (reader.has("reachability")) {
    io::JsonReader reach = reader.child("reachability");
    e->options_.unreachable_tolerance_deg = reach.non_negative("tolerance_deg", e->options_.unreachable_tolerance_deg);
    e->options_.unreachable_dwell_s = reach.non_negative("dwell_s", e->options_.unreachable_dwell_s);
    reach.finish();
  }
  const Repetitions repetitions = read_repetitions(reader);
  e->repetitions_ = repetitions.count;
  e->seed_ = repetitions.seed;

  e->read_controllers(reader, config, max_kpa);
  if (e->controllers_.size() == 1 && e->controllers_[0].name == "excitation") {
    // The routine is the run: the desired angle stays at neutral for as long as it lasts.
    if (reader.has("trajectory")) reader.fail("trajectory", "an excitation routine sets its own length; leave it out");
    const double duration_s = control::routine_duration_s(e->excitation_);
    e->trajectory_ = std::make_unique<control::StepTrajectory>(std::vector<control::WristAngles>{{}}, duration_s);
  } else {
    io::JsonReader trajectory = reader.child("trajectory");
    e->trajectory_ = read_trajectory(trajectory);
    trajectory.finish();
  }
  return e;
}

std::vector<Column> tracking_columns() {
  return {{"repetition", "", "repetition, from 0"},
          {"controller", "", "paper or model_based"},
          {"t_s", "s", "time from the start of the run (one row per control loop iteration)"},
          {"desired_fe_deg", "deg", "desired flexion (+) / extension (-)"},
          {"desired_ur_deg", "deg", "desired ulnar (+) / radial (-) deviation"},
          {"measured_fe_deg", "deg", "IMU pair's flexion/extension, zeroed at the start"},
          {"measured_ur_deg", "deg", "IMU pair's ulnar/radial deviation, zeroed at the start"},
          {"cmd_flexor_kpa", "kPa", "commanded pressure, flexor"},
          {"cmd_extensor_kpa", "kPa", "commanded pressure, extensor"},
          {"cmd_ulnar_kpa", "kPa", "commanded pressure, ulnar muscle"},
          {"cmd_radial_kpa", "kPa", "commanded pressure, radial muscle"},
          {"unreachable_fe", "", "1 while the flexion/extension target is reported out of reach"},
          {"unreachable_ur", "", "1 while the ulnar/radial target is reported out of reach"}};
}

Row tracking_row(int repetition, const std::string& controller, const control::TrackingSample& s) {
  return {std::to_string(repetition),
          controller,
          format_number(s.t_s),
          format_number(s.desired.angles.fe_deg),
          format_number(s.desired.angles.ur_deg),
          format_number(s.reading.angles.fe_deg),
          format_number(s.reading.angles.ur_deg),
          format_number(s.command[0]),
          format_number(s.command[1]),
          format_number(s.command[2]),
          format_number(s.command[3]),
          s.unreachable[0] ? "1" : "0",
          s.unreachable[1] ? "1" : "0"};
}

std::vector<Column> Tracking::columns() const {
  std::vector<Column> columns = tracking_columns();
  columns.push_back({"true_fe_deg", "deg", "the simulated joint's flexion/extension"});
  columns.push_back({"true_ur_deg", "deg", "the simulated joint's ulnar/radial deviation"});
  return columns;
}

std::vector<std::unique_ptr<control::Controller>> Tracking::make_controllers() const {
  std::vector<std::unique_ptr<control::Controller>> out;
  for (const ControllerSpec& spec : controllers_) out.push_back(spec.make());
  return out;
}

sim::SimulatedPlant Tracking::make_plant(std::uint64_t imu_seed) const {
  sim::ImuModel imu = imu_;
  imu.seed = imu_seed;
  return sim::SimulatedPlant(device_->model, units::pa_to_kpa(device_->description.regulator.max_pressure), imu);
}

std::vector<Row> Tracking::run_case(int index) const {
  const int repetition = index % repetitions_;
  const ControllerSpec& spec = controllers_[static_cast<std::size_t>(index / repetitions_)];
  std::mt19937_64 rng = case_rng(seed_, index);
  sim::SimulatedPlant plant = make_plant(rng());
  const std::unique_ptr<control::Controller> controller = spec.make();
  std::vector<Row> rows;
  rows.reserve(static_cast<std::size_t>(trajectory_->duration_s() / controller->period_s()) + 1);
  control::run_tracking(plant, *controller, *trajectory_, options_, [&](const control::TrackingSample& s) {
    const control::WristAngles truth = plant.true_angles();
    Row row = tracking_row(repetition, spec.name, s);
    row.push_back(format_number(truth.fe_deg));
    row.push_back(format_number(truth.ur_deg));
    rows.push_back(std::move(row));
  });
  return rows;
}

namespace {

// One run of the log: one controller, one repetition, in time order.
struct RunSeries {
  std::vector<double> t, desired_fe, desired_ur, measured_fe, measured_ur, true_fe, true_ur, unreachable_fe;
  double max_command_kpa = 0.0;
};

// The log's axis index (0 flexion/extension, 1 ulnar/radial) as the physics core's axis.
physics::WristAxis axis_of(int axis) {
  return axis == 0 ? physics::WristAxis::kFlexionExtension : physics::WristAxis::kUlnarRadial;
}

nlohmann::json number_or_null(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

double mean_of(const std::vector<double>& v) {
  double sum = 0.0;
  for (double x : v) sum += x;
  return v.empty() ? std::numeric_limits<double>::quiet_NaN() : sum / static_cast<double>(v.size());
}

// The log split into runs, the controllers in the order the log first names them.
struct TrackingRuns {
  std::vector<std::string> order;
  std::map<std::string, std::map<std::string, RunSeries>> runs;  // controller -> repetition -> series
  bool has_truth = false;
};

TrackingRuns read_runs(const io::CsvTable& log) {
  const int c_controller = log.column("controller"), c_repetition = log.column("repetition"), c_t = log.column("t_s");
  const int c_dfe = log.column("desired_fe_deg"), c_dur = log.column("desired_ur_deg");
  const int c_mfe = log.column("measured_fe_deg"), c_mur = log.column("measured_ur_deg");
  const int c_unreach = log.column("unreachable_fe");
  const std::array<int, 4> c_cmd = {log.column("cmd_flexor_kpa"), log.column("cmd_extensor_kpa"),
                                    log.column("cmd_ulnar_kpa"), log.column("cmd_radial_kpa")};
  // The true angles exist in simulated logs only; hardware logs have the IMUs alone.
  const int c_tfe = log.find_column("true_fe_deg"), c_tur = log.find_column("true_ur_deg");
  TrackingRuns out;
  out.has_truth = c_tfe >= 0 && c_tur >= 0;
  for (std::size_t row = 0; row < log.row_count(); ++row) {
    const std::string& name = log.cell(row, c_controller);
    if (!out.runs.contains(name)) out.order.push_back(name);
    RunSeries& r = out.runs[name][log.cell(row, c_repetition)];
    r.t.push_back(log.number(row, c_t));
    r.desired_fe.push_back(log.number(row, c_dfe));
    r.desired_ur.push_back(log.number(row, c_dur));
    r.measured_fe.push_back(log.number(row, c_mfe));
    r.measured_ur.push_back(log.number(row, c_mur));
    if (out.has_truth) {
      r.true_fe.push_back(log.number(row, c_tfe));
      r.true_ur.push_back(log.number(row, c_tur));
    }
    r.unreachable_fe.push_back(log.number(row, c_unreach));
    for (int c : c_cmd) r.max_command_kpa = std::max(r.max_command_kpa, log.number(row, c));
  }
  return out;
}

// What the summary of one controller needs besides its runs.
struct SummaryContext {
  const control::TrackingOptions& options;
  const physics::ReachableRange& reach;
  const control::StepTrajectory* step_trajectory;  // null unless the trajectory is a step sequence
  double settle_s;
  bool has_truth;
};

bool within_reach(const physics::ReachableRange& reach, double fe_deg, double ur_deg, int axis) {
  return reach.contains(axis_of(axis), units::deg_to_rad(axis == 0 ? fe_deg : ur_deg));
}

// RMSE of one axis over all repetitions after the settling time; `reachable_only` keeps the samples whose
// target the exosuit can hold.
double axis_rmse(const std::map<std::string, RunSeries>& reps, int axis, bool truth, bool reachable_only,
                 const SummaryContext& context) {
  std::vector<double> desired, actual;
  for (const auto& [rep, r] : reps) {
    const auto& d = axis == 0 ? r.desired_fe : r.desired_ur;
    const auto& a = truth ? (axis == 0 ? r.true_fe : r.true_ur) : (axis == 0 ? r.measured_fe : r.measured_ur);
    for (std::size_t i = 0; i < r.t.size(); ++i) {
      if (r.t[i] < context.settle_s) continue;
      if (reachable_only && !within_reach(context.reach, r.desired_fe[i], r.desired_ur[i], axis)) continue;
      desired.push_back(d[i]);
      actual.push_back(a[i]);
    }
  }
  return control::rms_error(desired, actual);
}

void add_rmse_figures(nlohmann::json& c, const std::map<std::string, RunSeries>& reps, const SummaryContext& context) {
  const char* axis_names[2] = {"fe", "ur"};
  for (int axis = 0; axis < 2; ++axis) {
    const bool active = context.options.active_axes[static_cast<std::size_t>(axis)];
    const std::string a = axis_names[axis];
    c["rmse_" + a + "_deg"] =
        active ? number_or_null(axis_rmse(reps, axis, false, false, context)) : nlohmann::json(nullptr);
    c["reachable_rmse_" + a + "_deg"] =
        active ? number_or_null(axis_rmse(reps, axis, false, true, context)) : nlohmann::json(nullptr);
    if (context.has_truth) {
      c["true_rmse_" + a + "_deg"] =
          active ? number_or_null(axis_rmse(reps, axis, true, false, context)) : nlohmann::json(nullptr);
    }
  }
}

// The responses of all repetitions to step `k` (from `from` to `to` deg flexion/extension).
struct StepResponses {
  std::vector<double> rises, overshoots, finals;
  bool flagged = false, all_reached = true;
};

StepResponses step_responses(const std::map<std::string, RunSeries>& reps, std::size_t k, double hold, double from,
                             double to, double tolerance_deg) {
  StepResponses out;
  for (const auto& [rep, r] : reps) {
    std::vector<double> t, y;
    for (std::size_t i = 0; i < r.t.size(); ++i) {
      const double local = r.t[i] - hold * static_cast<double>(k);
      if (local < 0.0 || local >= hold) continue;
      t.push_back(local);
      y.push_back(r.measured_fe[i]);
      if (local >= 0.5 * hold && r.unreachable_fe[i] > 0.5) out.flagged = true;
    }
    if (t.empty()) continue;
    const control::StepResponse response = control::step_response(t, y, from, to);
    out.rises.push_back(response.rise_time_s);
    out.overshoots.push_back(response.overshoot_pct);
    out.finals.push_back(response.final_error_deg);
    out.all_reached = out.all_reached && std::abs(response.final_error_deg) <= tolerance_deg;
  }
  return out;
}

// Step metrics of every step, and per direction the mean over the steps reached within the model's reach.
void add_step_figures(nlohmann::json& c, const std::map<std::string, RunSeries>& reps,
                      const control::StepTrajectory& step_trajectory, const SummaryContext& context) {
  const auto& levels = step_trajectory.levels();
  const double hold = step_trajectory.hold_s();
  nlohmann::json steps = nlohmann::json::array();
  std::map<std::string, std::vector<double>> rise, overshoot;  // by direction, reached steps only
  for (std::size_t k = 1; k < levels.size(); ++k) {
    const double from = levels[k - 1].fe_deg, to = levels[k].fe_deg;
    if (from == to) continue;
    const std::string direction = to < from ? "towards_extension" : "towards_flexion";
    const StepResponses responses = step_responses(reps, k, hold, from, to, context.options.unreachable_tolerance_deg);
    if (responses.rises.empty()) continue;
    const bool in_reach = within_reach(context.reach, to, 0.0, 0);
    steps.push_back({{"from_deg", from},
                     {"to_deg", to},
                     {"direction", direction},
                     {"rise_time_s", number_or_null(mean_of(responses.rises))},
                     {"overshoot_pct", mean_of(responses.overshoots)},
                     {"final_error_deg", mean_of(responses.finals)},
                     {"reached", responses.all_reached},
                     {"within_model_reach", in_reach},
                     {"reported_unreachable", responses.flagged}});
    if (responses.all_reached && in_reach && std::isfinite(mean_of(responses.rises))) {
      rise[direction].push_back(mean_of(responses.rises));
      overshoot[direction].push_back(mean_of(responses.overshoots));
    }
  }
  c["steps"] = steps;
  for (const std::string direction : {"towards_extension", "towards_flexion"}) {
    c[direction] = {{"rise_time_s", number_or_null(mean_of(rise[direction]))},
                    {"overshoot_pct", number_or_null(mean_of(overshoot[direction]))},
                    {"steps", rise[direction].size()}};
  }
}

nlohmann::json controller_summary(const std::string& name, const std::map<std::string, RunSeries>& reps,
                                  const SummaryContext& context) {
  nlohmann::json c = {{"controller", name}, {"repetitions", reps.size()}};
  add_rmse_figures(c, reps, context);
  double max_command = 0.0;
  for (const auto& [rep, r] : reps) max_command = std::max(max_command, r.max_command_kpa);
  c["max_command_kpa"] = max_command;

  if (context.step_trajectory != nullptr) add_step_figures(c, reps, *context.step_trajectory, context);
  return c;
}

// The error no controller can avoid: the distance from each target to the nearest angle the exosuit can hold.
nlohmann::json reach_limited_rmse_floor(const control::Trajectory& trajectory, double settle_s,
                                        const physics::ReachableRange& reach) {
  nlohmann::json floor;
  for (int axis = 0; axis < 2; ++axis) {
    std::vector<double> desired, held;
    const double step = 0.01;
    for (double t = settle_s; t < trajectory.duration_s(); t += step) {
      const control::WristAngles d = trajectory.at(t);
      const double v = axis == 0 ? d.fe_deg : d.ur_deg;
      desired.push_back(v);
      held.push_back(units::rad_to_deg(reach.clamp(axis_of(axis), units::deg_to_rad(v))));
    }
    floor[axis == 0 ? "fe" : "ur"] = number_or_null(control::rms_error(desired, held));
  }
  return floor;
}

}  // namespace

nlohmann::json Tracking::summarize(const io::CsvTable& log, const std::filesystem::path&) const {
  TrackingRuns runs = read_runs(log);

  // Step metrics apply to a step sequence only.
  const auto* step_trajectory = dynamic_cast<const control::StepTrajectory*>(trajectory_.get());
  const physics::ReachableRange reach = physics::reachable_range(sim::wrist_model(device_->description, gravity_),
                                                                 device_->description.regulator.max_pressure);
  const SummaryContext context{options_, reach, step_trajectory, settle_s_, runs.has_truth};

  nlohmann::json controllers = nlohmann::json::array();
  for (const std::string& name : runs.order) controllers.push_back(controller_summary(name, runs.runs[name], context));

  const nlohmann::json floor = reach_limited_rmse_floor(*trajectory_, settle_s_, reach);

  return {{"trajectory", step_trajectory != nullptr ? "steps" : "sinusoid"},
          {"settle_s", settle_s_},
          {"hand_supported", gravity_ == 0.0},
          {"reachable_range_deg",
           {{"flexion", units::rad_to_deg(reach.flexion)},
            {"extension", units::rad_to_deg(reach.extension)},
            {"ulnar", units::rad_to_deg(reach.ulnar)},
            {"radial", units::rad_to_deg(reach.radial)}}},
          {"reach_limited_rmse_floor_deg", floor},
          {"controllers", controllers},
          {"paper", kPaperFigures},
          {"explanation",
           "rmse_*_deg compares the IMU angles (zeroed at the start, as in the paper) with the desired angles after "
           "settle_s; reachable_rmse_* keeps only the samples whose target lies within reachable_range_deg (each "
           "muscle alone at the regulator's maximum, from the analytic statics); true_rmse_* uses the simulated "
           "joint angles instead of the IMUs. reach_limited_rmse_floor_deg is the RMSE no controller can beat on "
           "this device: the distance from the targets to the reachable range. Rise time (10-90 %) and overshoot "
           "use the IMU angle with a 0.05 s moving average; the per-direction figures average the steps reached "
           "within the model's reach. The paper's figures are in 'paper'."}};
}

}  // namespace softwrist::experiments
