#pragma once
// Torque validation (Section Torque applied by the exosuit, Fig. ExperimentalData): one muscle (the flexor) on a
// wrist held at fixed angles while the regulator fills it to each pressure, its torque about the joint measured
// with a noisy torque sensor, its mounts tracked by noisy motion-capture markers, a few repetitions. The summary
// models the torque the paper's three ways (fixed placement without stretching, fixed placement with the one-shot
// stretching of Eqn. fabric_stretching, and the placement from the measured mount positions) and gives the MAE of
// each against the measurement, beside the paper's 1.111, 0.283 and 0.350 N m.

#include <memory>

#include "experiments/experiment.h"
#include "experiments/simulated_device.h"

namespace softwrist::experiments {

struct TorqueNoise {
  // Assumed, configurable (no values in the paper): the spread of repeated readings at one angle and pressure.
  double torque_std = 0.02;       // [N m] sensor noise and re-seating of the hand plate
  double angle_jitter = 0.01745;  // [rad] (1 deg) the relaxed wrist's actual angle on the plate
  double marker_std = 0.002;      // [m] a marker on the fPAM's end knot (Section Results of the torque
                                  // measurement: "challenging to attach the markers directly to the end")
};

class TorqueValidation final : public Experiment {
 public:
  static std::unique_ptr<TorqueValidation> Create(const ExperimentConfig& config, io::JsonReader& reader);

  std::string kind() const override { return "torque_validation"; }
  std::vector<Column> columns() const override;
  int case_count() const override;
  std::vector<Row> run_case(int index) const override;
  std::string model_hash() const override { return device_->model_hash; }
  nlohmann::json summarize(const io::CsvTable& log, const std::filesystem::path& run_dir) const override;

 private:
  std::unique_ptr<SimulatedDevice> device_;
  sim::MuscleIndex muscle_ = sim::kFlexor;
  std::vector<double> angles_;     // [rad], in the wrist's convention (flexion positive)
  std::vector<double> pressures_;  // [Pa]
  int repetitions_ = 3;
  std::uint64_t seed_ = 1;
  double hold_time_ = 1.0;  // [s]
  TorqueNoise noise_;
};

}  // namespace softwrist::experiments
