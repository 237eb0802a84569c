#include "experiments/torque_validation.h"

#include <cmath>
#include <fstream>
#include <map>

#include <fmt/format.h>

#include "io/csv.h"
#include "physics/mount_points.h"
#include "physics/paper_parameters.h"
#include "physics/units.h"
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

int TorqueValidation::case_count() const {
  return static_cast<int>(angles_.size() * pressures_.size()) * repetitions_;
}

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
  const bool fe = sim::joint_of(muscle_) == sim::WristJoint::kFlexionExtension;
  wrist.run_held(hold_time_, fe ? actual_angle : 0.0, fe ? 0.0 : actual_angle);
  const double torque = wrist.muscle_torque(muscle_) + noise_.torque_std * normal(rng);

  // Where the markers on the mounts are: the mounts moved by the device's own stretching at the simulated force.
  const auto& mount = device_->description.muscles[muscle_];
  const double own_angle = sim::direction_of(muscle_) * actual_angle;
  const double force = std::abs(wrist.data()->actuator_force[muscle_]);
  const auto points = device_->description.stretch_mode == physics::StretchMode::kNone
                          ? physics::mount_points(mount.placement, own_angle)
                          : physics::stretched_mount_points(mount.placement, mount.wrist_radius, own_angle, force,
                                                            device_->description.mount_stiffness);
  const auto marker = [&](double coordinate) { return format_number(units::m_to_cm(coordinate + noise_.marker_std * normal(rng))); };
  return {{std::to_string(repetition), format_number(rad_to_deg(angles_[angle_index])),
           format_number(units::pa_to_kpa(pressure)), format_number(rad_to_deg(actual_angle)), format_number(torque),
           marker(points.forearm.x), marker(points.forearm.y), marker(points.hand.x), marker(points.hand.y)}};
}

nlohmann::json TorqueValidation::summarize(const io::CsvTable& log, const std::filesystem::path& run_dir) const {
  const int c_set = log.column("angle_set_deg"), c_pressure = log.column("pressure_kpa"),
            c_angle = log.column("angle_deg"), c_torque = log.column("torque_nm");
  const int c_p1x = log.column("p1_x_cm"), c_p1y = log.column("p1_y_cm"), c_p2x = log.column("p2_x_cm"),
            c_p2y = log.column("p2_y_cm");
  const sim::DeviceDescription& device = device_->description;
  const double direction = sim::direction_of(muscle_);

  // The analytic muscle with each stretching variant; the stiffness is the device's.
  const auto muscle_with = [&](physics::StretchMode mode) {
    physics::Muscle m = device.muscle(muscle_);
    m.stretch_mode = mode;
    return m;
  };
  const bool has_stiffness = device.mount_stiffness.forearm != 0.0 && device.mount_stiffness.hand != 0.0;
  struct Method {
    std::string name;
    std::string description;
  };
  std::vector<Method> methods = {{"fixed_no_stretch", "fixed initial placement, no mount stretching (paper's third method)"},
                                 {"motion_capture", "placement from the measured mount positions (paper's first method)"}};
  if (has_stiffness) {
    methods.push_back({"fixed_stretch", "fixed placement, one-shot Eqn. fabric_stretching (paper's second method)"});
    methods.push_back({"fixed_stretch_selfconsistent", "fixed placement, self-consistent Eqn. fabric_stretching"});
  }
  const auto model_torque = [&](const std::string& method, std::size_t row) {
    const double own_angle = direction * deg_to_rad(log.number(row, c_angle));
    const double pressure = units::kpa_to_pa(log.number(row, c_pressure));
    if (method == "fixed_no_stretch") return physics::muscle_state(muscle_with(physics::StretchMode::kNone), own_angle, pressure).torque;
    if (method == "fixed_stretch") return physics::muscle_state(muscle_with(physics::StretchMode::kOneShot), own_angle, pressure).torque;
    if (method == "fixed_stretch_selfconsistent") {
      return physics::muscle_state(muscle_with(physics::StretchMode::kSelfConsistent), own_angle, pressure).torque;
    }
    physics::Muscle m = muscle_with(physics::StretchMode::kNone);
    const physics::MountPoints measured{{cm_to_m(log.number(row, c_p1x)), cm_to_m(log.number(row, c_p1y))},
                                        {cm_to_m(log.number(row, c_p2x)), cm_to_m(log.number(row, c_p2y))}};
    m.placement = physics::placement_from_mount_points(measured, own_angle);
    return physics::muscle_state(m, own_angle, pressure).torque;
  };

  // Groups of repetitions at one nominal angle and pressure: mean measured torque against the mean model torque
  // at the repetitions' measured angles (the paper compares against the mean of its three measurements).
  struct Group {
    int count = 0;
    double angle = 0.0, torque = 0.0, torque_sq = 0.0;
    std::map<std::string, double> model;
  };
  std::map<std::pair<double, double>, Group> groups;
  for (std::size_t row = 0; row < log.row_count(); ++row) {
    Group& g = groups[{log.number(row, c_pressure), log.number(row, c_set)}];
    const double torque = log.number(row, c_torque);
    g.count += 1;
    g.angle += log.number(row, c_angle);
    g.torque += torque;
    g.torque_sq += torque * torque;
    for (const auto& m : methods) g.model[m.name] += model_torque(m.name, row);
  }
  nlohmann::json table = nlohmann::json::array();
  std::map<std::string, double> absolute_error;
  std::map<double, std::map<std::string, double>> error_by_pressure;
  std::map<double, int> groups_by_pressure;
  double mean_abs_torque = 0.0;
  for (auto& [key, g] : groups) {
    const double mean = g.torque / g.count;
    const double variance = g.count > 1 ? std::max(0.0, (g.torque_sq - g.count * mean * mean) / (g.count - 1)) : 0.0;
    nlohmann::json entry = {{"pressure_kpa", key.first}, {"angle_set_deg", key.second},
                            {"angle_deg", g.angle / g.count}, {"torque_nm", mean},
                            {"torque_std_nm", std::sqrt(variance)}, {"repetitions", g.count}};
    for (const auto& m : methods) {
      const double model = g.model[m.name] / g.count;
      entry["model_" + m.name + "_nm"] = model;
      absolute_error[m.name] += std::abs(model - mean);
      error_by_pressure[key.first][m.name] += std::abs(model - mean);
    }
    groups_by_pressure[key.first] += 1;
    mean_abs_torque += std::abs(mean);
    table.push_back(entry);
  }
  const double n = static_cast<double>(groups.size());
  nlohmann::json mae, mae_percent, method_descriptions, per_pressure = nlohmann::json::array();
  for (const auto& m : methods) {
    mae[m.name] = absolute_error[m.name] / n;
    mae_percent[m.name] = 100.0 * absolute_error[m.name] / mean_abs_torque;
    method_descriptions[m.name] = m.description;
  }
  for (const auto& [pressure, errors] : error_by_pressure) {
    nlohmann::json entry = {{"pressure_kpa", pressure}};
    for (const auto& [name, sum] : errors) entry["mae_" + name + "_nm"] = sum / groups_by_pressure[pressure];
    per_pressure.push_back(entry);
  }

  // Model curves on a 1-degree grid for the plots.
  {
    io::CsvWriter curves(run_dir / "model_curves.csv",
                         {"pressure_kpa", "angle_deg", "fixed_no_stretch_nm", "fixed_stretch_nm", "fixed_stretch_selfconsistent_nm"});
    for (const double pressure : pressures_) {
      const double lo = rad_to_deg(*std::min_element(angles_.begin(), angles_.end()));
      const double hi = rad_to_deg(*std::max_element(angles_.begin(), angles_.end()));
      for (double a = lo; a <= hi + 1e-9; a += 1.0) {
        const double own = direction * deg_to_rad(a);
        const auto torque = [&](physics::StretchMode mode) {
          if (mode != physics::StretchMode::kNone && !has_stiffness) return std::string("");
          return format_number(physics::muscle_state(muscle_with(mode), own, pressure).torque);
        };
        curves.write_row({format_number(units::pa_to_kpa(pressure)), format_number(a),
                          torque(physics::StretchMode::kNone), torque(physics::StretchMode::kOneShot),
                          torque(physics::StretchMode::kSelfConsistent)});
      }
    }
  }
  return {{"muscle", sim::kMuscleNames[muscle_]},
          {"mae_nm", mae},
          {"mae_percent_of_mean_torque", mae_percent},
          {"paper_mae_nm", kPaperMae},
          {"paper_mae_percent_of_mean_torque", {{"fixed_no_stretch", 108.7}, {"fixed_stretch", 27.7}, {"motion_capture", 34.3}}},
          {"methods", method_descriptions},
          {"mean_abs_torque_nm", mean_abs_torque / n},
          {"mae_by_pressure", per_pressure},
          {"groups", table},
          {"files", {{"model_curves", "model_curves.csv"}}},
          {"note", fmt::format("The simulated measurement is the MuJoCo model with the device's own mount stretching "
                               "({}), 3D tendon wrapping and the noise model of the config; the methods are the "
                               "analytic 2D model.",
                               physics::to_string(device.stretch_mode))}};
}

}  // namespace softwrist::experiments
