#pragma once
// Design optimization (Section Design Optimization): the placement of one fPAM that brings its modeled torque up
// to a reference profile, by multi-start local search from the grid of Table optimized_parameters (one case per
// start, so the starts run on threads or in shards), checked against an exhaustive grid search, and the smallest
// pressure at which an optimized placement meets the reference everywhere.

#include <memory>
#include <optional>

#include "experiments/experiment.h"
#include "optimize/design_optimizer.h"

namespace softwrist::experiments {

// The design section of a config or a user file (docs/experiments.md), read into the optimizer's terms.
struct DesignSettings {
  optimize::DesignProblem problem;
  optimize::OptimizerOptions options;
  std::optional<optimize::PressureSearch> pressure_search;
  std::optional<physics::Placement> exhaustive_resolution;  // [m]
  std::string reference_text;                               // the reference CSV as read, for the provenance hash
};
DesignSettings read_design_settings(io::JsonReader& reader, const ExperimentConfig& config);

class DesignOptimization final : public Experiment {
 public:
  static std::unique_ptr<DesignOptimization> Create(const ExperimentConfig& config, io::JsonReader& reader);

  std::string kind() const override { return "design_optimization"; }
  std::vector<Column> columns() const override;
  int case_count() const override { return static_cast<int>(starts_.size()); }
  std::vector<Row> run_case(int index) const override;
  std::string model_hash() const override;
  nlohmann::json summarize(const io::CsvTable& log, const std::filesystem::path& run_dir) const override;

 private:
  DesignSettings settings_;
  std::vector<physics::Placement> starts_;
};

}  // namespace softwrist::experiments
