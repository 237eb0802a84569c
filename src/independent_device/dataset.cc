#include "independent_device/dataset.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <stdexcept>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "independent_device/effects.h"
#include "independent_device/rigs.h"
#include "independent_device/units.h"

namespace softwrist::independent {
namespace {

using ordered_json = nlohmann::ordered_json;

// Conventions of one dataset (drawn per seed): what the torque sensor's reading includes and the arm's postures.
struct Conventions {
  std::string torque_includes;
  Posture sweep_posture = Posture::hand_supported;
  Posture rom_posture = Posture::hand_supported;
  Posture ellipse_posture = Posture::gravity_fe;
};

const char* posture_name(Posture p) {
  switch (p) {
    case Posture::gravity_fe:
      return "gravity_fe";
    case Posture::gravity_ur:
      return "gravity_ur";
    case Posture::hand_supported:
      break;
  }
  return "hand_supported";
}

Conventions draw_conventions(std::uint64_t seed) {
  Rng rng(seed, "conventions");
  static const std::array<const char*, 4> kIncludes{"muscle", "muscle+passive_wrist",
                                                    "muscle+passive_wrist+hand_weight", "baseline_subtracted"};
  Conventions c;
  c.torque_includes = kIncludes[std::min<std::size_t>(3, static_cast<std::size_t>(rng.uniform() * 4.0))];
  const double u = rng.uniform();
  // The rig turns in the horizontal plane (hand supported) unless the sensor also weighs the hand; with a baseline
  // subtracted, either set-up.
  if (c.torque_includes == "muscle+passive_wrist+hand_weight")
    c.sweep_posture = Posture::gravity_fe;
  else if (c.torque_includes == "baseline_subtracted" && u < 0.5)
    c.sweep_posture = Posture::gravity_fe;
  static const std::array<Posture, 3> kRom{Posture::hand_supported, Posture::gravity_fe, Posture::gravity_ur};
  c.rom_posture = kRom[std::min<std::size_t>(2, static_cast<std::size_t>(rng.uniform() * 3.0))];
  c.ellipse_posture = rng.uniform() < 0.5 ? Posture::gravity_fe : Posture::gravity_ur;
  return c;
}

struct DataFile {
  std::string csv, kind, rig;
  Table table;
  std::vector<std::vector<std::string>> groups;  // measured columns compared for the magnitude
  std::vector<std::string> group_names;
};

std::vector<DataFile> run_session(const DeviceSpec& device, const DatasetOptions& options, const Conventions& c,
                                  bool noisy) {
  Session s(device, options.seed, noisy);
  std::vector<DataFile> files;
  files.push_back({"tensile.csv", "tensile", "torque_rig", run_tensile(s), {{"force_n"}}, {"force_n"}});
  s.clock_s += 300.0;  // the fPAM goes from the tester onto the rig
  files.push_back({"torque_sweep.csv",
                   "torque-sweep",
                   "torque_rig",
                   run_torque_sweep(s, c.torque_includes, c.sweep_posture, options.sweep_repetitions),
                   {{"torque_nm"}},
                   {"torque_nm"}});
  s.clock_s += 600.0;  // the prototype is donned
  files.push_back({"rom.csv",
                   "rom",
                   "prototype",
                   run_rom(s, c.rom_posture, options.rom_repetitions),
                   {{"limit_deg"}},
                   {"limit_deg"}});
  s.clock_s += 300.0;
  const std::vector<std::vector<std::string>> trajectory_groups{
      {"angle_fe_deg", "angle_ur_deg"}, {"p_flexor_kpa", "p_extensor_kpa", "p_ulnar_kpa", "p_radial_kpa"}};
  const std::vector<std::string> trajectory_names{"angles", "measured_pressures"};
  // Three planar and four spatial trials, as in the paper's Figs. Demonstration_positioning and _trajectory.
  files.push_back({"trajectory_steps.csv", "trajectory", "prototype",
                   run_tracking(s, TrackingTask::planar_steps, Posture::hand_supported, 3, options.trajectory_s),
                   trajectory_groups, trajectory_names});
  s.clock_s += 120.0;
  files.push_back({"trajectory_ellipse.csv", "trajectory", "prototype",
                   run_tracking(s, TrackingTask::ellipse, c.ellipse_posture, 4, options.trajectory_s),
                   trajectory_groups, trajectory_names});
  return files;
}

double rms_difference(const Table& a, const Table& b, const std::vector<std::string>& columns) {
  double sum = 0.0;
  std::size_t n = 0;
  for (const auto& column : columns) {
    const auto x = a.numbers(column), y = b.numbers(column);
    for (std::size_t i = 0; i < x.size(); ++i) {
      sum += (x[i] - y[i]) * (x[i] - y[i]);
      ++n;
    }
  }
  return n ? std::sqrt(sum / static_cast<double>(n)) : 0.0;
}

void write_text(const std::filesystem::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw std::runtime_error(fmt::format("cannot write {}", path.string()));
  out << text;
  if (!out) throw std::runtime_error(fmt::format("cannot write {}", path.string()));
}

ordered_json manifest_entry(const DataFile& f, const Conventions& c) {
  ordered_json e;
  e["csv"] = f.csv;
  e["kind"] = f.kind;
  e["rig"] = f.rig;
  if (f.kind == "tensile") return e;  // no wrist, no angles
  if (f.kind == "torque-sweep") {
    e["muscle"] = "flexor";
    e["torque_includes"] = c.torque_includes;
    e["posture"] = posture_name(c.sweep_posture);
    e["angles_zeroed_at_start"] = false;  // plate angles, set with screws
  } else if (f.kind == "rom") {
    e["posture"] = posture_name(c.rom_posture);
    e["angles_zeroed_at_start"] = true;
  } else {
    e["posture"] = f.csv == "trajectory_steps.csv" ? "hand_supported" : posture_name(c.ellipse_posture);
    e["angles_zeroed_at_start"] = true;
  }
  e["angle_resolution_deg"] = 0.0625;
  return e;
}

void check_dataset_options(const DatasetOptions& options) {
  validate_effects(options.effects);
  if (!(options.trajectory_s > 0.0 && options.trajectory_s <= 3600.0))
    throw std::invalid_argument(fmt::format("trajectory_s {} is outside (0, 3600]", options.trajectory_s));
  if (options.sweep_repetitions < 1 || options.rom_repetitions < 1)
    throw std::invalid_argument("sweep_repetitions and rom_repetitions must be at least 1");
}

ordered_json effect_json(const EffectSpec& e, const EffectDefinition& def, const nlohmann::json& parameters) {
  ordered_json ej;
  ej["form"] = e.form;
  ej["label"] = def.info.label;
  ej["level"] = e.level;
  ej["description"] = def.info.description;
  ej["parameters"] = parameters;
  return ej;
}

struct AppliedEffects {
  ordered_json json = ordered_json::array();
  bool any = false;  // an effect other than "none"
};

// Applies the effects to `device` in order, recording them and their labels (or "none") in `truth`.
AppliedEffects apply_effects(const std::vector<EffectSpec>& effects, DeviceSpec& device, DatasetTruth& truth) {
  AppliedEffects applied;
  for (const auto& e : effects) {
    const EffectDefinition* def = find_effect(e.form);
    nlohmann::json parameters = nlohmann::json::object();
    def->apply(device, e.level, parameters);
    truth.effects.push_back(e);
    if (def->info.label != "none") {
      applied.any = true;
      if (std::find(truth.labels.begin(), truth.labels.end(), def->info.label) == truth.labels.end())
        truth.labels.push_back(def->info.label);
    }
    applied.json.push_back(effect_json(e, *def, parameters));
  }
  if (truth.labels.empty()) truth.labels.push_back("none");
  return applied;
}

// The file's group of measured columns where the effect stands out most from the noise.
struct FileEffect {
  FileMagnitude magnitude;
  double effect_over_noise = -1.0;
};

FileEffect largest_effect(const DataFile& with, const DataFile& without, const DataFile& clean) {
  FileEffect best{{with.csv, 0.0, 0.0, with.group_names.front()}};
  for (std::size_t g = 0; g < with.groups.size(); ++g) {
    const double effect = rms_difference(with.table, without.table, with.groups[g]);
    const double noise = rms_difference(without.table, clean.table, with.groups[g]);
    const double ratio = noise > 0.0 ? effect / noise : 0.0;
    if (ratio > best.effect_over_noise) {
      best.effect_over_noise = ratio;
      best.magnitude = {with.csv, effect, noise, with.group_names[g]};
    }
  }
  return best;
}

ordered_json file_effect_json(const FileEffect& f) {
  ordered_json fj;
  fj["csv"] = f.magnitude.csv;
  fj["quantity"] = f.magnitude.quantity;
  fj["effect_rms"] = f.magnitude.effect_rms;
  fj["noise_sd"] = f.magnitude.noise_sd;
  fj["effect_over_noise"] = f.effect_over_noise;
  return fj;
}

// Writes the CSVs (with the effects) and manifest.json; records each file's effect size in `truth` and returns
// them for truth.json.
ordered_json write_data_files(const std::filesystem::path& out_dir, const std::vector<DataFile>& with,
                              const std::vector<DataFile>& without, const std::vector<DataFile>& clean,
                              const Conventions& conventions, DatasetTruth& truth) {
  ordered_json manifest;
  manifest["format"] = "softwrist.independent/1";
  manifest["files"] = ordered_json::array();
  ordered_json files_json = ordered_json::array();
  for (std::size_t i = 0; i < with.size(); ++i) {
    const DataFile& f = with[i];
    write_text(out_dir / f.csv, f.table.csv());
    manifest["files"].push_back(manifest_entry(f, conventions));
    const FileEffect best = largest_effect(f, without[i], clean[i]);
    truth.files.push_back(best.magnitude);
    truth.magnitude_noise_units = std::max(truth.magnitude_noise_units, best.effect_over_noise);
    files_json.push_back(file_effect_json(best));
  }
  write_text(out_dir / "manifest.json", manifest.dump(2) + "\n");
  return files_json;
}

}  // namespace

double nominal_torque_rig_torque_nm(double angle_deg, double pressure_kpa) {
  static const DeviceSpec device = nominal_device();
  return torque_rig_flexor(device, MuscleState{}, to_rad(angle_deg), pressure_kpa).torque_nm;
}

DatasetTruth write_dataset(const DatasetOptions& options, const std::filesystem::path& out_dir) {
  check_dataset_options(options);

  const Conventions conventions = draw_conventions(options.seed);
  DeviceSpec nominal = nominal_device();
  Rng variation_rng(options.seed, "device-variation");
  const nlohmann::json variation = apply_variation(nominal, variation_rng);
  DeviceSpec effected = nominal;
  DatasetTruth truth;
  const AppliedEffects effects = apply_effects(options.effects, effected, truth);

  // The same noise realisation with and without the effects, and a noise-free run for the noise's size.
  const std::vector<DataFile> without = run_session(nominal, options, conventions, true);
  const std::vector<DataFile> with = effects.any ? run_session(effected, options, conventions, true) : without;
  const std::vector<DataFile> clean = run_session(nominal, options, conventions, false);

  std::filesystem::create_directories(out_dir);
  const ordered_json files_json = write_data_files(out_dir, with, without, clean, conventions, truth);

  ordered_json tj;
  tj["format"] = "softwrist.independent.truth/1";
  tj["seed"] = options.seed;
  tj["effects"] = effects.json;
  tj["labels"] = truth.labels;
  tj["magnitude_noise_units"] = truth.magnitude_noise_units;
  tj["files"] = files_json;
  tj["conventions"] = {{"torque_includes", conventions.torque_includes},
                       {"sweep_posture", posture_name(conventions.sweep_posture)},
                       {"rom_posture", posture_name(conventions.rom_posture)},
                       {"ellipse_posture", posture_name(conventions.ellipse_posture)}};
  tj["device_variation"] = variation;
  tj["notes"] =
      "effect_rms: rms over the file's measured columns of (with effects - without), same noise realisation; "
      "noise_sd: rms of (without effects, noisy - noise-free); a trajectory reports the larger ratio of its "
      "angles and its measured pressures";
  write_text(out_dir / "truth.json", tj.dump(2) + "\n");
  return truth;
}

}  // namespace softwrist::independent
