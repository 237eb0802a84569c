#pragma once
// Range of motion (Section Range of motion, Table RoM): each muscle alone at 137 kPa moves the relaxed wrist until
// it settles; the settled angle in the muscle's direction is measured with motion-capture noise. The summary puts
// it beside the analytic model's joint limit (the paper's "modeled" limit: the angle where the muscle's torque
// reaches zero), the analytic statics with everything the simulation contains (wrist_statics.h), and the paper's
// measured exosuit and biological ranges.

#include <memory>

#include "experiments/experiment.h"
#include "experiments/simulated_device.h"
#include "physics/exosuit_layout.h"

namespace softwrist::experiments {

class RangeOfMotion final : public Experiment {
 public:
  static std::unique_ptr<RangeOfMotion> Create(const ExperimentConfig& config, io::JsonReader& reader);

  std::string kind() const override { return "range_of_motion"; }
  std::vector<Column> columns() const override;
  int case_count() const override { return static_cast<int>(muscles_.size()) * repetitions_; }
  std::vector<Row> run_case(int index) const override;
  std::string model_hash() const override { return device_->model_hash; }
  nlohmann::json summarize(const io::CsvTable& log, const std::filesystem::path& run_dir) const override;

 private:
  std::unique_ptr<SimulatedDevice> device_;
  std::vector<sim::MuscleIndex> muscles_;
  double pressure_ = physics::kRegulatorMaxPressure;  // [Pa]
  int repetitions_ = 3;
  std::uint64_t seed_ = 1;
  double settle_time_ = 6.0;   // [s]
  double angle_std_ = 0.0087;  // [rad] (0.5 deg) motion-capture angle noise, assumed
};

}  // namespace softwrist::experiments
