#pragma once
// An INDEPENDENT "real device" data generator for benchmarking softwrist's sim-to-real gap diagnosis: a soft
// wrist exosuit with four fPAMs, after the paper (shared/paper/soft-wrist-exosuit-fpam.tex), written apart from
// softwrist's own model. write_dataset() writes, into one directory, what real rigs give: a torque sweep of the
// torque rig's flexor, a range-of-motion test and closed-loop tracking trials of the prototype, and a tensile test
// of the fPAM, as CSV files with sensor noise and quantisation, plus manifest.json (what a user states when
// importing) and truth.json (the injected effects and the gap they cause, in noise units).

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace softwrist::independent {

struct EffectSpec {
  std::string form;
  double level = 1.0;
};

struct DatasetOptions {
  std::uint64_t seed = 1;
  std::vector<EffectSpec> effects;  // empty: nominal (with device-to-device variation)
  double trajectory_s = 24.0;       // length of each tracking trial
  int sweep_repetitions = 2, rom_repetitions = 2;
};

struct FormInfo {
  std::string name, label, description, parameter;
  double value_at_level_1 = 0.0;
};
const std::vector<FormInfo>& effect_forms();

struct FileMagnitude {
  std::string csv;
  double effect_rms = 0.0, noise_sd = 0.0;
  std::string quantity;  // the measured columns compared (a trajectory reports its larger of angles / pressures)
};

struct DatasetTruth {
  std::vector<EffectSpec> effects;
  std::vector<std::string> labels;
  std::vector<FileMagnitude> files;
  double magnitude_noise_units = 0.0;
};

// Writes the CSVs, manifest.json and truth.json into out_dir (created). Throws std::invalid_argument naming an
// unknown form or a level outside (0, 1].
DatasetTruth write_dataset(const DatasetOptions& options, const std::filesystem::path& out_dir);

// The nominal torque rig's static flexor torque [N m] at a wrist angle [deg] and pressure [kPa] (no noise, no
// variation, no friction history): for a cross-check against softwrist's analytic model. It includes the mounts'
// stretch (paper Eq. fabric_stretching) solved self-consistently.
double nominal_torque_rig_torque_nm(double angle_deg, double pressure_kpa);

}  // namespace softwrist::independent
