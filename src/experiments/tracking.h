#pragma once
// Trajectory tracking (Section Control and Demonstration): each controller drives the simulated exosuit
// (sim::SimulatedPlant: the MuJoCo wrist with the fPAM plugin, the regulators' lag and the IMU pair) along the
// desired trajectory through control::run_tracking, the loop the hardware bridge runs too. One case per controller
// and repetition (each repetition its own IMU offset and noise); the log holds every loop iteration. The summary
// puts the controllers side by side: RMSE per axis after the initial settling, and for a step trajectory the rise
// time and overshoot of every step, the targets out of the exosuit's reach, and the paper's figures.

#include <functional>
#include <memory>

#include "control/controller.h"
#include "control/excitation_controller.h"
#include "control/tracking_loop.h"
#include "control/trajectory.h"
#include "experiments/experiment.h"
#include "experiments/simulated_device.h"
#include "sim/simulated_plant.h"

namespace softwrist::experiments {

// The columns every tracking log has, whatever ran it (the simulation adds the true joint angles, a hardware trial
// the measured pressures), and one loop iteration's row in them.
std::vector<Column> tracking_columns();
Row tracking_row(int repetition, const std::string& controller, const control::TrackingSample& sample);

// Gives every model_based controller of a tracking config `placement` as its model of the device (the config's
// "model" of that controller). Returns false when the config has none.
bool set_controller_model(nlohmann::json& config, const std::filesystem::path& placement);

class Tracking final : public Experiment {
 public:
  static std::unique_ptr<Tracking> Create(const ExperimentConfig& config, io::JsonReader& reader);

  std::string kind() const override { return "tracking"; }
  std::vector<Column> columns() const override;
  int case_count() const override { return static_cast<int>(controllers_.size()) * repetitions_; }
  std::vector<Row> run_case(int index) const override;
  std::string model_hash() const override { return device_->model_hash; }
  nlohmann::json summarize(const io::CsvTable& log, const std::filesystem::path& run_dir) const override;

  // The controllers in the config's order, freshly made (for the benchmark).
  std::vector<std::unique_ptr<control::Controller>> make_controllers() const;
  const control::Trajectory& trajectory() const { return *trajectory_; }
  // A new simulated plant with the config's IMU model for this seed.
  sim::SimulatedPlant make_plant(std::uint64_t imu_seed) const;
  const control::TrackingOptions& options() const { return options_; }
  int repetitions() const { return repetitions_; }
  // The excitation routine's schedule when the config's controller is "excitation"; empty otherwise.
  const std::vector<control::ExcitationSegment>& excitation() const { return excitation_; }

 private:
  struct ControllerSpec {
    std::string name;
    std::function<std::unique_ptr<control::Controller>()> make;
  };
  // The config's "controllers" list (the excitation routine, when it is the one, into excitation_).
  void read_controllers(io::JsonReader& reader, const ExperimentConfig& config, double max_kpa);

  std::unique_ptr<SimulatedDevice> device_;
  std::vector<ControllerSpec> controllers_;
  std::vector<control::ExcitationSegment> excitation_;
  std::unique_ptr<control::Trajectory> trajectory_;
  control::TrackingOptions options_;
  sim::ImuModel imu_;
  double gravity_ = 9.81;  // [m/s^2], 0 with the hand supported
  double settle_s_ = 3.0;  // excluded from the RMSE
  int repetitions_ = 3;
  std::uint64_t seed_ = 1;
};

}  // namespace softwrist::experiments
