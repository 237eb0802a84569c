#include "experiments/torque_validation.h"

#include <cmath>
#include <fstream>
#include <map>

#include <fmt/format.h>

#include "io/csv.h"
#include "physics/mount_points.h"
#include "physics/paper_parameters.h"
#include "physics/torque_geometry.h"
#include "physics/units.h"
#include "sim/device.h"
#include "sim/wrist_sim.h"

namespace softwrist::experiments {
namespace {

using io::format_number;
using units::cm_to_m;
using units::deg_to_rad;
using units::rad_to_deg;

sim::MuscleIndex muscle_named(io::JsonReader& reader, const std::string& key) {
  const std::string name = reader.text(key, "flexor");
  if (const auto muscle = sim::muscle_from_name(name)) return *muscle;
  reader.fail(key, fmt::format("'{}' is not flexor, extensor, ulnar or radial", name));
}

// The paper's MAE of each torque method (Section Torque applied by the exosuit).
const nlohmann::json kPaperMae = {{"fixed_no_stretch", 1.111}, {"fixed_stretch", 0.283}, {"motion_capture", 0.350}};

// The log's columns the summary reads.
struct TorqueColumns {
  int set, pressure, angle, torque, p1x, p1y, p2x, p2y;
};

TorqueColumns torque_columns(const io::CsvTable& log) {
  return {log.column("angle_set_deg"), log.column("pressure_kpa"), log.column("angle_deg"), log.column("torque_nm"),
          log.column("p1_x_cm"),       log.column("p1_y_cm"),      log.column("p2_x_cm"),   log.column("p2_y_cm")};
}

// The analytic muscle with one stretching variant; the stiffness is the device's.
physics::Muscle muscle_with(const sim::DeviceDescription& device, sim::MuscleIndex muscle, physics::StretchMode mode) {
  physics::Muscle m = device.muscle(muscle);
  m.stretch_mode = mode;
  return m;
}

bool has_mount_stiffness(const sim::DeviceDescription& device) {
  return device.mount_stiffness.forearm != 0.0 && device.mount_stiffness.hand != 0.0;
}

struct TorqueMethod {
  std::string name;
  std::string description;
};

std::vector<TorqueMethod> torque_methods(bool has_stiffness) {
  std::vector<TorqueMethod> methods = {
      {"fixed_no_stretch", "fixed initial placement, no mount stretching (paper's third method)"},
      {"motion_capture", "placement from the measured mount positions (paper's first method)"}};
  if (has_stiffness) {
    methods.push_back({"fixed_stretch", "fixed placement, one-shot Eqn. fabric_stretching (paper's second method)"});
    methods.push_back({"fixed_stretch_selfconsistent", "fixed placement, self-consistent Eqn. fabric_stretching"});
  }
  return methods;
}

// The torque `method` models for the log's `row`, at the row's measured angle (and mount positions).
double method_torque(const sim::DeviceDescription& device, sim::MuscleIndex muscle, const std::string& method,
                     const io::CsvTable& log, const TorqueColumns& c, std::size_t row) {
  const double own_angle = physics::direction_of(muscle) * deg_to_rad(log.number(row, c.angle));
  const double pressure = units::kpa_to_pa(log.number(row, c.pressure));
  const auto fixed_placement = [&](physics::StretchMode mode) {
    return physics::muscle_state(muscle_with(device, muscle, mode), own_angle, pressure).torque;
  };
  if (method == "fixed_no_stretch") return fixed_placement(physics::StretchMode::kNone);
  if (method == "fixed_stretch") return fixed_placement(physics::StretchMode::kOneShot);
  if (method == "fixed_stretch_selfconsistent") return fixed_placement(physics::StretchMode::kSelfConsistent);
  physics::Muscle m = muscle_with(device, muscle, physics::StretchMode::kNone);
  const physics::MountPoints measured{{cm_to_m(log.number(row, c.p1x)), cm_to_m(log.number(row, c.p1y))},
                                      {cm_to_m(log.number(row, c.p2x)), cm_to_m(log.number(row, c.p2y))}};
  m.placement = physics::placement_from_mount_points(measured, own_angle);
  return physics::muscle_state(m, own_angle, pressure).torque;
}

// The repetitions at one nominal angle and pressure: sums of the measured and of each method's model torque.
struct RepetitionGroup {
  int count = 0;
  double angle = 0.0, torque = 0.0, torque_sq = 0.0;
  std::map<std::string, double> model;
};
using RepetitionGroups = std::map<std::pair<double, double>, RepetitionGroup>;  // by (pressure, nominal angle)

RepetitionGroups group_repetitions(const sim::DeviceDescription& device, sim::MuscleIndex muscle,
                                   const std::vector<TorqueMethod>& methods, const io::CsvTable& log,
                                   const TorqueColumns& c) {
  RepetitionGroups groups;
  for (std::size_t row = 0; row < log.row_count(); ++row) {
    RepetitionGroup& g = groups[{log.number(row, c.pressure), log.number(row, c.set)}];
    const double torque = log.number(row, c.torque);
    g.count += 1;
    g.angle += log.number(row, c.angle);
    g.torque += torque;
    g.torque_sq += torque * torque;
    for (const auto& m : methods) g.model[m.name] += method_torque(device, muscle, m.name, log, c, row);
  }
  return groups;
}

// Each group's mean measured and model torques, and the absolute errors of the methods summed over the groups.
struct GroupComparison {
  nlohmann::json table = nlohmann::json::array();
  std::map<std::string, double> absolute_error;
  std::map<double, std::map<std::string, double>> error_by_pressure;
  std::map<double, int> groups_by_pressure;
  double mean_abs_torque = 0.0;  // the sum over the groups until divided by their number
};

GroupComparison compare_groups(RepetitionGroups& groups, const std::vector<TorqueMethod>& methods) {
  GroupComparison out;
  for (auto& [key, g] : groups) {
    const double mean = g.torque / g.count;
    const double variance = g.count > 1 ? std::max(0.0, (g.torque_sq - g.count * mean * mean) / (g.count - 1)) : 0.0;
    nlohmann::json entry = {
        {"pressure_kpa", key.first}, {"angle_set_deg", key.second},          {"angle_deg", g.angle / g.count},
        {"torque_nm", mean},         {"torque_std_nm", std::sqrt(variance)}, {"repetitions", g.count}};
    for (const auto& m : methods) {
      const double model = g.model[m.name] / g.count;
      entry["model_" + m.name + "_nm"] = model;
      out.absolute_error[m.name] += std::abs(model - mean);
      out.error_by_pressure[key.first][m.name] += std::abs(model - mean);
    }
    out.groups_by_pressure[key.first] += 1;
    out.mean_abs_torque += std::abs(mean);
    out.table.push_back(entry);
  }
  return out;
}

// The MAE of each method over `n` groups, overall and by pressure.
struct MethodErrors {
  nlohmann::json mae, mae_percent, method_descriptions, per_pressure = nlohmann::json::array();
};

MethodErrors method_errors(GroupComparison& comparison, const std::vector<TorqueMethod>& methods, double n) {
  MethodErrors out;
  for (const auto& m : methods) {
    out.mae[m.name] = comparison.absolute_error[m.name] / n;
    out.mae_percent[m.name] = 100.0 * comparison.absolute_error[m.name] / comparison.mean_abs_torque;
    out.method_descriptions[m.name] = m.description;
  }
  for (const auto& [pressure, errors] : comparison.error_by_pressure) {
    nlohmann::json entry = {{"pressure_kpa", pressure}};
    for (const auto& [name, sum] : errors) entry["mae_" + name + "_nm"] = sum / comparison.groups_by_pressure[pressure];
    out.per_pressure.push_back(entry);
  }
  return out;
}

// Model curves on a 1-degree grid for the plots.
void write_model_curves(const std::filesystem::path& path, const sim::DeviceDescription& device,
                        sim::MuscleIndex muscle, const std::vector<double>& angles,
                        const std::vector<double>& pressures) {
  const double direction = physics::direction_of(muscle);
  const bool has_stiffness = has_mount_stiffness(device);
  io::CsvWriter curves(path, {"pressure_kpa", "angle_deg", "fixed_no_stretch_nm", "fixed_stretch_nm",
                              "fixed_stretch_selfconsistent_nm"});
  for (const double pressure : pressures) {
    const double lo = rad_to_deg(*std::min_element(angles.begin(), angles.end()));
    const double hi = rad_to_deg(*std::max_element(angles.begin(), angles.end()));
    for (double a = lo; a <= hi + 1e-9; a += 1.0) {
      const double own = direction * deg_to_rad(a);
      const auto torque = [&](physics::StretchMode mode) {
        if (mode != physics::StretchMode::kNone && !has_stiffness) return std::string("");
        return format_number(physics::muscle_state(muscle_with(device, muscle, mode), own, pressure).torque);
      };
      curves.write_row({format_number(units::pa_to_kpa(pressure)), format_number(a),
                        torque(physics::StretchMode::kNone), torque(physics::StretchMode::kOneShot),
                        torque(physics::StretchMode::kSelfConsistent)});
    }
  }
}

}  // namespace

std::unique_ptr<TorqueValidation> TorqueValidation::Create(const ExperimentConfig& config, io::JsonReader& reader) {
  auto experiment = std::unique_ptr<TorqueValidation>(new TorqueValidation());
  experiment->device_ = std::make_unique<SimulatedDevice>(config_path(reader, "model", config));
  experiment->muscle_ = muscle_named(reader, "muscle");
  std::vector<double> angles_deg = {-67.5, -45.0, -22.5, 0.0, 22.5, 45.0, 67.5, 90.0};
  if (reader.has("angles_deg")) angles_deg = reader.numbers("angles_deg");
  for (double a : angles_deg) {
    if (std::abs(a) > 90.0) reader.fail("angles_deg", fmt::format("{} is outside -90..90", a));
    experiment->angles_.push_back(deg_to_rad(a));
  }
  std::vector<double> pressures_kpa(physics::paper::kMeasurementPressures.begin(),
                                    physics::paper::kMeasurementPressures.end());
  for (double& p : pressures_kpa) p = units::pa_to_kpa(p);
  if (reader.has("pressures_kpa")) pressures_kpa = reader.numbers("pressures_kpa");
  for (double p : pressures_kpa) {
    experiment->pressures_.push_back(experiment->device_->regulator_pressure(reader, "pressures_kpa", p));
  }
  const Repetitions repetitions = read_repetitions(reader);
  experiment->repetitions_ = repetitions.count;
  experiment->seed_ = repetitions.seed;
  experiment->hold_time_ = reader.positive("hold_time_s", 1.0);
  if (reader.has("sensor_noise")) {
    io::JsonReader noise = reader.child("sensor_noise");
    experiment->noise_.torque_std = noise.non_negative("torque_std_nm", 0.02);
    experiment->noise_.angle_jitter = deg_to_rad(noise.non_negative("angle_jitter_deg", 1.0));
    experiment->noise_.marker_std = cm_to_m(0.1 * noise.non_negative("marker_std_mm", 2.0));
    noise.finish();
  }
  return experiment;
}

std::vector<Column> TorqueValidation::columns() const {
  return {{"repetition", "", "repetition of this angle and pressure, from 0"},
          {"angle_set_deg", "deg", "nominal wrist angle of the hand plate, flexion positive"},
          {"pressure_kpa", "kPa", "commanded pressure"},
          {"angle_deg", "deg", "measured wrist angle, flexion positive"},
          {"torque_nm", "N m", "measured torque of the muscle about the joint, positive in its own direction"},
          {"p1_x_cm", "cm", "measured forearm mount, x along the forearm (2D frame of the muscle's plane)"},
          {"p1_y_cm", "cm", "measured forearm mount, y towards the muscle's side"},
          {"p2_x_cm", "cm", "measured hand mount, x"},
          {"p2_y_cm", "cm", "measured hand mount, y"}};
}

int TorqueValidation::case_count() const { return static_cast<int>(angles_.size() * pressures_.size()) * repetitions_; }

std::vector<Row> TorqueValidation::run_case(int index) const {
  const int repetition = index % repetitions_;
  const std::size_t pressure_index = static_cast<std::size_t>(index / repetitions_) % pressures_.size();
  const std::size_t angle_index = static_cast<std::size_t>(index / repetitions_) / pressures_.size();
  std::mt19937_64 rng = case_rng(seed_, index);
  std::normal_distribution<double> normal(0.0, 1.0);
  const double actual_angle = angles_[angle_index] + noise_.angle_jitter * normal(rng);
  const double pressure = pressures_[pressure_index];

  // The rig: the wrist held, the other muscles not attached (their torque is not part of the reading).
  sim::WristSim wrist(device_->model);
  std::array<double, 4> command{};
  command[muscle_] = units::pa_to_kpa(pressure);
  wrist.command_pressures_kpa(command);
  const bool fe = physics::axis_of(muscle_) == physics::WristAxis::kFlexionExtension;
  wrist.run_held(hold_time_, fe ? actual_angle : 0.0, fe ? 0.0 : actual_angle);
  const double torque = wrist.muscle_torque(muscle_) + noise_.torque_std * normal(rng);

  // Where the markers on the mounts are: the mounts moved by the device's own stretching at the simulated force.
  const auto& mount = device_->description.muscles[muscle_];
  const double own_angle = physics::direction_of(muscle_) * actual_angle;
  // The pull: minus the tendon's actuator force, or (routing planar: the actuator's force is its torque) the torque
  // over the 2D path's moment arm.
  const bool planar = device_->description.routing == sim::Routing::kPlanar;
  const double force =
      planar ? std::abs(
                   wrist.muscle_torque(muscle_) /
                   physics::muscle_path(mount.placement, mount.wrist_radius, own_angle, mount.wrap_surface).moment_arm)
             : std::abs(wrist.data()->actuator_force[muscle_]);
  const auto points = device_->description.stretch_mode == physics::StretchMode::kNone
                          ? physics::mount_points(mount.placement, own_angle)
                          : physics::stretched_mount_points(mount.placement, mount.wrist_radius, own_angle, force,
                                                            device_->description.mount_stiffness, mount.wrap_surface);
  const auto marker = [&](double coordinate) {
    return format_number(units::m_to_cm(coordinate + noise_.marker_std * normal(rng)));
  };
  return {{std::to_string(repetition), format_number(rad_to_deg(angles_[angle_index])),
           format_number(units::pa_to_kpa(pressure)), format_number(rad_to_deg(actual_angle)), format_number(torque),
           marker(points.forearm.x), marker(points.forearm.y), marker(points.hand.x), marker(points.hand.y)}};
}

nlohmann::json TorqueValidation::summarize(const io::CsvTable& log, const std::filesystem::path& run_dir) const {
  const TorqueColumns c = torque_columns(log);
  const sim::DeviceDescription& device = device_->description;
  const std::vector<TorqueMethod> methods = torque_methods(has_mount_stiffness(device));

  // Groups of repetitions at one nominal angle and pressure: mean measured torque against the mean model torque
  // at the repetitions' measured angles (the paper compares against the mean of its three measurements).
  RepetitionGroups groups = group_repetitions(device, muscle_, methods, log, c);
  GroupComparison comparison = compare_groups(groups, methods);
  const double n = static_cast<double>(groups.size());
  const MethodErrors errors = method_errors(comparison, methods, n);

  write_model_curves(run_dir / "model_curves.csv", device, muscle_, angles_, pressures_);
  return {{"muscle", sim::kMuscleNames[muscle_]},
          {"mae_nm", errors.mae},
          {"mae_percent_of_mean_torque", errors.mae_percent},
          {"paper_mae_nm", kPaperMae},
          {"paper_mae_percent_of_mean_torque",
           {{"fixed_no_stretch", 108.7}, {"fixed_stretch", 27.7}, {"motion_capture", 34.3}}},
          {"methods", errors.method_descriptions},
          {"mean_abs_torque_nm", comparison.mean_abs_torque / n},
          {"mae_by_pressure", errors.per_pressure},
          {"groups", comparison.table},
          {"files", {{"model_curves", "model_curves.csv"}}},
          {"note", fmt::format("The simulated measurement is the MuJoCo model with the device's own mount stretching "
                               "({}), 3D tendon wrapping and the noise model of the config; the methods are the "
                               "analytic 2D model.",
                               physics::to_string(device.stretch_mode))}};
}

}  // namespace softwrist::experiments
