#include "independent_device/dataset.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

#include <nlohmann/json.hpp>

#include "independent_device/device.h"
#include "independent_device/effects.h"
#include "independent_device/geometry.h"
#include "independent_device/random.h"
#include "independent_device/rigs.h"
#include "independent_device/units.h"

namespace softwrist::independent {
namespace {

namespace fs = std::filesystem;

// A CSV as written: header and string cells.
struct Csv {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  int column(const std::string& name) const {
    const auto it = std::find(header.begin(), header.end(), name);
    return it == header.end() ? -1 : static_cast<int>(it - header.begin());
  }
  std::vector<double> numbers(const std::string& name) const {
    const int c = column(name);
    std::vector<double> out;
    for (const auto& r : rows) out.push_back(std::stod(r.at(static_cast<std::size_t>(c))));
    return out;
  }
  std::vector<std::string> texts(const std::string& name) const {
    const int c = column(name);
    std::vector<std::string> out;
    for (const auto& r : rows) out.push_back(r.at(static_cast<std::size_t>(c)));
    return out;
  }
};

std::string slurp(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

Csv read_csv(const fs::path& path) {
  Csv csv;
  std::stringstream in(slurp(path));
  std::string line;
  bool first = true;
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::stringstream ls(line);
    std::string cell;
    while (std::getline(ls, cell, ',')) cells.push_back(cell);
    if (first) {
      csv.header = cells;
      first = false;
    } else {
      csv.rows.push_back(cells);
    }
  }
  return csv;
}

nlohmann::json read_json(const fs::path& path) { return nlohmann::json::parse(slurp(path)); }

// A scratch directory of this process, empty at the start and removed when it goes out of scope (a suite run left
// some 1900 of them in /tmp before).
class Scratch {
 public:
  explicit Scratch(const std::string& name)
      : dir_(fs::temp_directory_path() / ("softwrist_independent_test_" + std::to_string(::getpid()) + "_" + name)) {
    fs::remove_all(dir_);
  }
  Scratch(Scratch&& other) noexcept : dir_(std::move(other.dir_)) { other.dir_.clear(); }
  Scratch(const Scratch&) = delete;
  Scratch& operator=(const Scratch&) = delete;
  Scratch& operator=(Scratch&&) = delete;
  ~Scratch() {
    std::error_code ignored;
    if (!dir_.empty()) fs::remove_all(dir_, ignored);
  }
  operator const fs::path&() const { return dir_; }  // NOLINT(google-explicit-constructor): used as the path
  fs::path operator/(const fs::path& file) const { return dir_ / file; }

 private:
  fs::path dir_;
};

// Short trials keep the suite quick; the rigs are the same.
DatasetOptions quick(std::uint64_t seed, std::vector<EffectSpec> effects = {}) {
  DatasetOptions o;
  o.seed = seed;
  o.effects = std::move(effects);
  o.trajectory_s = 8.0;
  o.rom_repetitions = 1;
  return o;
}

const std::vector<std::string> kFiles{"tensile.csv", "torque_sweep.csv", "rom.csv", "trajectory_steps.csv",
                                      "trajectory_ellipse.csv"};

double rms_difference(const std::vector<double>& a, const std::vector<double>& b) {
  double sum = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) sum += (a[i] - b[i]) * (a[i] - b[i]);
  return std::sqrt(sum / static_cast<double>(a.size()));
}

bool on_grid(double value, double steps_per_unit) {
  return std::abs(value * steps_per_unit - std::round(value * steps_per_unit)) < 1e-6;
}

// ---- determinism, manifest, formats ------------------------------------------------------------------------

TEST(IndependentDataset, SameSeedAndOptionsGiveByteIdenticalFiles) {
  const auto options = quick(11, {{"dahl_friction", 0.5}, {"forearm_imu_roll", 0.7}});
  const Scratch a("det_a"), b("det_b"), c("det_c");
  write_dataset(options, a);
  write_dataset(options, b);
  auto other = options;
  other.seed = 12;
  write_dataset(other, c);
  for (const auto& f : kFiles) {
    EXPECT_TRUE(slurp(a / f) == slurp(b / f)) << f;
    EXPECT_TRUE(slurp(a / f) != slurp(c / f)) << f;
  }
  EXPECT_TRUE(slurp(a / "manifest.json") == slurp(b / "manifest.json"));
  EXPECT_TRUE(slurp(a / "truth.json") == slurp(b / "truth.json"));
}

TEST(IndependentDataset, ManifestIsTrueToTheFiles) {
  const Scratch dir("manifest");
  const auto options = quick(5);
  write_dataset(options, dir);
  const auto manifest = read_json(dir / "manifest.json");
  EXPECT_EQ(manifest.at("format"), "softwrist.independent/1");
  const std::map<std::string, std::vector<std::string>> required{
      {"torque-sweep", {"angle_deg", "pressure_kpa", "torque_nm", "repetition", "muscle"}},
      {"rom", {"muscle", "pressure_kpa", "limit_deg", "repetition"}},
      {"tensile", {"pressure_kpa", "contraction", "force_n", "direction", "cycle"}},
      {"trajectory",
       {"t_s", "cmd_flexor_kpa", "cmd_extensor_kpa", "cmd_ulnar_kpa", "cmd_radial_kpa", "angle_fe_deg", "angle_ur_deg",
        "case", "p_flexor_kpa", "p_extensor_kpa", "p_ulnar_kpa", "p_radial_kpa"}}};
  std::set<std::string> kinds;
  ASSERT_EQ(manifest.at("files").size(), kFiles.size());
  for (const auto& entry : manifest.at("files")) {
    const std::string kind = entry.at("kind");
    kinds.insert(kind);
    const Csv csv = read_csv(dir / entry.at("csv").get<std::string>());
    ASSERT_FALSE(csv.rows.empty()) << entry.dump();
    for (const auto& column : required.at(kind)) EXPECT_GE(csv.column(column), 0) << kind << " " << column;
    for (const auto& row : csv.rows) ASSERT_EQ(row.size(), csv.header.size());
    const std::string rig = entry.at("rig");
    EXPECT_TRUE(rig == "torque_rig" || rig == "prototype");
    if (kind == "tensile") continue;
    const std::string posture = entry.at("posture");
    EXPECT_TRUE(posture == "hand_supported" || posture == "gravity_fe" || posture == "gravity_ur");
    EXPECT_EQ(entry.at("angle_resolution_deg"), 0.0625);
    if (kind == "torque-sweep") {
      EXPECT_EQ(entry.at("muscle"), "flexor");
      const std::string inc = entry.at("torque_includes");
      EXPECT_TRUE(inc == "muscle" || inc == "muscle+passive_wrist" || inc == "muscle+passive_wrist+hand_weight" ||
                  inc == "baseline_subtracted");
      if (inc == "muscle+passive_wrist+hand_weight") {
        EXPECT_EQ(posture, "gravity_fe");
      }
      EXPECT_FALSE(entry.at("angles_zeroed_at_start").get<bool>());
      // 8 angles x 5 pressures per repetition; repetitions alternate ascending and descending angles.
      ASSERT_EQ(csv.rows.size(), 8u * 5u * static_cast<std::size_t>(options.sweep_repetitions));
      const auto angles = csv.numbers("angle_deg");
      EXPECT_EQ(angles.front(), -67.5);
      EXPECT_EQ(angles[39], 90.0);
      EXPECT_EQ(angles[40], 90.0);
      EXPECT_EQ(angles[79], -67.5);
      for (const auto& m : csv.texts("muscle")) EXPECT_EQ(m, "flexor");
      if (inc == "baseline_subtracted") {
        const auto p = csv.numbers("pressure_kpa"), torque = csv.numbers("torque_nm");
        for (std::size_t i = 0; i < p.size(); ++i)
          if (p[i] == 0.0) {
            EXPECT_EQ(torque[i], 0.0);
          }
      }
    } else if (kind == "rom") {
      EXPECT_EQ(csv.rows.size(), 4u * 4u * static_cast<std::size_t>(options.rom_repetitions));
      std::set<std::string> muscles;
      for (const auto& m : csv.texts("muscle")) muscles.insert(m);
      EXPECT_EQ(muscles, (std::set<std::string>{"flexor", "extensor", "ulnar", "radial"}));
      EXPECT_TRUE(entry.at("angles_zeroed_at_start").get<bool>());
    } else {
      EXPECT_TRUE(entry.at("angles_zeroed_at_start").get<bool>());
      // Logged at the control rate; zeroed at each trial's start.
      const auto t = csv.numbers("t_s"), fe = csv.numbers("angle_fe_deg"), ur = csv.numbers("angle_ur_deg");
      const auto cases = csv.texts("case");
      for (std::size_t i = 0; i < t.size(); ++i) {
        if (i == 0 || cases[i] != cases[i - 1]) {
          EXPECT_EQ(t[i], 0.0);
          EXPECT_EQ(fe[i], 0.0);
          EXPECT_EQ(ur[i], 0.0);
        } else {
          EXPECT_NEAR(t[i] - t[i - 1], 0.014, 1e-9);
        }
      }
      if (entry.at("csv") == "trajectory_steps.csv") {
        EXPECT_EQ(posture, "hand_supported");
      }
    }
  }
  EXPECT_EQ(kinds, (std::set<std::string>{"torque-sweep", "rom", "tensile", "trajectory"}));
}

TEST(IndependentDataset, EveryTorqueConventionOccursAcrossSeeds) {
  // The convention is drawn per seed; check the draw covers all four (cheaply, without writing data).
  std::set<std::string> seen;
  for (std::uint64_t seed = 1; seed <= 40; ++seed) {
    Rng rng(seed, "conventions");
    seen.insert(std::to_string(std::min<int>(3, static_cast<int>(rng.uniform() * 4.0))));
  }
  EXPECT_EQ(seen.size(), 4u);
}

TEST(IndependentDataset, SensorsQuantiseAsRealRigs) {
  const Scratch dir("quantise");
  write_dataset(quick(7, {{"latency_jitter", 1.0}}), dir);
  for (const auto* name : {"trajectory_steps.csv", "trajectory_ellipse.csv"}) {
    const Csv csv = read_csv(dir / name);
    for (const auto* col : {"angle_fe_deg", "angle_ur_deg"})
      for (const double v : csv.numbers(col)) ASSERT_TRUE(on_grid(v, 16.0)) << name << " " << col << " " << v;
    for (const auto* col : {"p_flexor_kpa", "p_extensor_kpa", "p_ulnar_kpa", "p_radial_kpa"})
      for (const double v : csv.numbers(col)) ASSERT_TRUE(on_grid(v, 10.0) && v >= 0.0) << col << " " << v;
  }
  for (const double v : read_csv(dir / "rom.csv").numbers("limit_deg")) ASSERT_TRUE(on_grid(v, 16.0)) << v;
  for (const double v : read_csv(dir / "torque_sweep.csv").numbers("torque_nm")) ASSERT_TRUE(on_grid(v, 1000.0)) << v;
  for (const double v : read_csv(dir / "tensile.csv").numbers("force_n")) ASSERT_TRUE(on_grid(v, 10.0)) << v;
  // Shortest round-trip numbers: no 0.30000000000000004-style cells.
  const std::string text = slurp(dir / "trajectory_steps.csv");
  EXPECT_EQ(text.find("00000000"), std::string::npos);
}

// ---- the nominal torque rig ----------------------------------------------------------------------------------

TEST(IndependentTorqueRig, NominalTorqueHasThePhysicalShape) {
  const std::vector<double> angles{-67.5, -45.0, -22.5, 0.0, 22.5, 45.0, 67.5, 90.0};
  for (const double a : angles) {
    // Deflated: only the fabric's elastic term, which pulls only where the fabric is stretched past e0.
    EXPECT_GE(nominal_torque_rig_torque_nm(a, 0.0), 0.0);
    EXPECT_LT(nominal_torque_rig_torque_nm(a, 0.0), 0.1 * nominal_torque_rig_torque_nm(a, 137.0) + 1e-3) << a;
    if (a >= 0.0) {
      EXPECT_LT(nominal_torque_rig_torque_nm(a, 0.0), 0.05) << a;
    }
    for (const double p : {34.0, 68.0, 103.0, 137.0}) EXPECT_GE(nominal_torque_rig_torque_nm(a, p), 0.0);
    EXPECT_EQ(nominal_torque_rig_torque_nm(90.0, 137.0), 0.0);
  }
  // Positive in flexion and growing with pressure where the muscle is far from its maximum contraction.
  for (const double a : {-67.5, -45.0, -22.5, 0.0}) {
    double previous = nominal_torque_rig_torque_nm(a, 0.0);
    for (const double p : {34.0, 68.0, 103.0, 137.0}) {
      const double t = nominal_torque_rig_torque_nm(a, p);
      EXPECT_GT(t, previous) << a << " deg " << p << " kPa";
      previous = t;
    }
  }
  EXPECT_GT(nominal_torque_rig_torque_nm(22.5, 68.0), 0.5);
  EXPECT_GT(nominal_torque_rig_torque_nm(-67.5, 137.0), 3.0);
}

TEST(IndependentTorqueRig, TorqueVanishesAtThePressureDependentMaximumContraction) {
  const DeviceSpec device = nominal_device();
  for (const double p : {34.0, 68.0, 103.0, 137.0}) {
    double angle = 0.0;
    MuscleForce last;
    while (angle < 90.0) {
      const MuscleForce f = torque_rig_flexor(device, MuscleState{}, to_rad(angle), p);
      if (f.torque_nm <= 0.0) break;
      last = f;
      angle += 0.05;
    }
    ASSERT_LT(angle, 90.0) << p;
    // Just before the torque vanishes the muscle is at its maximum contraction for this pressure (Table tensile).
    EXPECT_NEAR(last.contraction, max_contraction(device.rig_flexor.law, p), 2e-3) << p;
  }
}

TEST(IndependentGeometry, MomentArmIsMinusTheLengthDerivative) {
  const Placement rig{0.1947, 0.0493, 0.0830, 0.0338};
  const std::vector<WrapSurface> surfaces{
      {0.0399, 0.0399, 0.0, 0.0}, {0.0399 * 1.3, 0.0399 * 0.75, 0.0, 0.0}, {0.0399, 0.0399, -0.008, 0.008}};
  for (const auto& wrap : surfaces) {
    bool saw_wrap = false, saw_straight = false;
    for (double deg = -80.0; deg <= 80.0; deg += 2.5) {
      const double th = to_rad(deg), h = 1e-6;
      const Path p = muscle_path(rig, wrap, th);
      const double dl = (muscle_path(rig, wrap, th + h).length_m - muscle_path(rig, wrap, th - h).length_m) / (2 * h);
      EXPECT_NEAR(p.moment_arm_m, -dl, 1e-6) << deg;
      (p.wrapped ? saw_wrap : saw_straight) = true;
    }
    EXPECT_TRUE(saw_wrap && saw_straight);
    // The path length is continuous where the muscle starts to wrap.
    for (double deg = -80.0; deg <= 80.0; deg += 0.01) {
      const Path a = muscle_path(rig, wrap, to_rad(deg)), b = muscle_path(rig, wrap, to_rad(deg + 0.01));
      EXPECT_LT(std::abs(a.length_m - b.length_m), 1e-4);
    }
  }
  // The circle gives the paper's moment arm r_w when wrapped (force tangent to the wrist circle about O).
  const Path wrapped = muscle_path(rig, surfaces[0], to_rad(-67.5));
  ASSERT_TRUE(wrapped.wrapped);
  EXPECT_NEAR(wrapped.moment_arm_m, 0.0399, 1e-9);
}

// ---- effects -------------------------------------------------------------------------------------------------

TEST(IndependentEffects, CatalogueHasTwoFormsPerLabelAndThreeOutside) {
  std::map<std::string, int> per_label;
  std::set<std::string> names;
  for (const auto& f : effect_forms()) {
    EXPECT_TRUE(names.insert(f.name).second) << f.name;
    ++per_label[f.label];
    if (f.name != "none") {
      EXPECT_FALSE(f.description.empty());
      EXPECT_FALSE(f.parameter.empty());
      EXPECT_NE(f.value_at_level_1, 0.0);
    }
  }
  for (const auto* label :
       {"mount_stretch", "fpam_params", "regulator_lag", "hysteresis", "wrap_geometry", "passive_wrist", "imu_bias"})
    EXPECT_GE(per_label[label], 2) << label;
  int outside = 0;
  for (const auto& [label, n] : per_label) outside += label.rfind("outside:", 0) == 0 ? 1 : 0;
  EXPECT_GE(outside, 3);
  EXPECT_EQ(per_label["none"], 1);
}

TEST(IndependentEffects, BadFormOrLevelIsAnErrorNamingIt) {
  const Scratch dir("errors");
  auto expect_message = [&](const std::vector<EffectSpec>& effects, const std::string& needle) {
    try {
      write_dataset(quick(1, effects), dir);
      ADD_FAILURE() << "no error for " << needle;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  expect_message({{"wobbly_wrist", 1.0}}, "wobbly_wrist");
  expect_message({{"dahl_friction", 0.0}}, "dahl_friction");
  expect_message({{"dahl_friction", 1.5}}, "1.5");
  expect_message({{"slow_vent", std::nan("")}}, "slow_vent");
  expect_message({{"slow_vent", -0.2}}, "-0.2");
  expect_message({{"slow_vent", 0.5}, {"slow_vent", 0.5}}, "slow_vent");
  EXPECT_FALSE(fs::exists(dir / "manifest.json"));
}

struct EffectRun {
  Scratch dir;
  DatasetTruth truth;
};

EffectRun run(const std::string& tag, std::uint64_t seed, std::vector<EffectSpec> effects) {
  EffectRun r{Scratch(tag), {}};
  r.truth = write_dataset(quick(seed, std::move(effects)), r.dir);
  return r;
}

TEST(IndependentEffects, HysteresisSeparatesLoadingFromUnloadingAndSweepDirections) {
  // Seed 2 draws the "muscle" torque convention (load-cell noise only), so the sweep's history shows clearly.
  const EffectRun nominal = run("hyst_nominal", 2, {});
  ASSERT_EQ(read_json(nominal.dir / "manifest.json").at("files").at(1).at("torque_includes"), "muscle");
  for (const auto* form : {"dahl_friction", "maxwell_slip"}) {
    const EffectRun effect = run(std::string("hyst_") + form, 2, {{form, 1.0}});
    // Tensile: at the same contraction, stretching (loading) needs more force than unloading.
    auto gap = [](const fs::path& dir) {
      const Csv t = read_csv(dir / "tensile.csv");
      std::map<std::tuple<std::string, std::string, std::string>, double> loading;
      double sum = 0.0;
      int n = 0;
      for (const auto& r : t.rows) {
        const auto key = std::make_tuple(r[0], r[1], r[4]);
        if (r[3] == "loading") loading[key] = std::stod(r[2]);
      }
      for (const auto& r : t.rows) {
        const auto key = std::make_tuple(r[0], r[1], r[4]);
        if (r[3] == "unloading" && std::stod(r[0]) > 0.0 && std::stod(r[1]) < 0.2 && loading.count(key)) {
          sum += loading[key] - std::stod(r[2]);
          ++n;
        }
      }
      return sum / n;
    };
    EXPECT_LT(std::abs(gap(nominal.dir)), 0.3);
    EXPECT_GT(gap(effect.dir), 3.0) << form;
    // Sweep: ascending (shortening) repetitions read less torque than descending ones at the same point.
    auto sweep_gap = [](const fs::path& dir) {
      const Csv s = read_csv(dir / "torque_sweep.csv");
      std::map<std::pair<std::string, std::string>, std::map<std::string, double>> by_point;
      for (const auto& r : s.rows) by_point[{r[0], r[1]}][r[3]] = std::stod(r[2]);
      double sum = 0.0;
      int n = 0;
      for (const auto& [key, reps] : by_point)
        if (key.second == "34" || key.second == "68") {
          sum += reps.at("1") - reps.at("2");
          ++n;
        }
      return sum / n;
    };
    EXPECT_LT(std::abs(sweep_gap(nominal.dir)), 0.01);
    EXPECT_LT(sweep_gap(effect.dir), -0.04) << form;
  }
}

TEST(IndependentEffects, RegulatorFormsChangeTheMeasuredPressureResponse) {
  const EffectRun nominal = run("reg_nominal", 4, {});
  for (const auto* form : {"second_order_response", "slow_vent", "rate_limit_dead_time"}) {
    const EffectRun effect = run(std::string("reg_") + form, 4, {{form, 1.0}});
    // Static tensile holds do not see a regulator's dynamics.
    EXPECT_TRUE(slurp(nominal.dir / "tensile.csv") == slurp(effect.dir / "tensile.csv")) << form;
    // The measured pressures lag the commands differently: compare (measured - commanded) across runs.
    double worst = 0.0;
    for (const auto* file : {"trajectory_steps.csv", "trajectory_ellipse.csv"}) {
      const Csv a = read_csv(nominal.dir / file), b = read_csv(effect.dir / file);
      for (const auto* m : {"flexor", "extensor", "ulnar", "radial"}) {
        const std::string p = std::string("p_") + m + "_kpa", c = std::string("cmd_") + m + "_kpa";
        auto lag = [&](const Csv& t) {
          auto measured = t.numbers(p);
          const auto command = t.numbers(c);
          for (std::size_t i = 0; i < measured.size(); ++i) measured[i] -= command[i];
          return measured;
        };
        worst = std::max(worst, rms_difference(lag(a), lag(b)));
      }
    }
    EXPECT_GT(worst, 0.45) << form;  // three times the monitor's noise
  }
}

TEST(IndependentEffects, ImuFormsChangeOnlyAngles) {
  const EffectRun nominal = run("imu_nominal", 6, {});
  for (const auto* form : {"forearm_imu_roll", "latency_jitter"}) {
    const EffectRun effect = run(std::string("imu_") + form, 6, {{form, 1.0}});
    // No IMU on the tensile tester or the torque rig: byte-identical.
    EXPECT_TRUE(slurp(nominal.dir / "tensile.csv") == slurp(effect.dir / "tensile.csv")) << form;
    EXPECT_TRUE(slurp(nominal.dir / "torque_sweep.csv") == slurp(effect.dir / "torque_sweep.csv")) << form;
    const Csv a = read_csv(nominal.dir / "trajectory_ellipse.csv"), b = read_csv(effect.dir / "trajectory_ellipse.csv");
    EXPECT_GT(std::max(rms_difference(a.numbers("angle_fe_deg"), b.numbers("angle_fe_deg")),
                       rms_difference(a.numbers("angle_ur_deg"), b.numbers("angle_ur_deg"))),
              0.3)
        << form;
  }
  // The roll misalignment shows even in open loop: the range-of-motion limits change.
  const EffectRun roll = run("imu_roll_rom", 6, {{"forearm_imu_roll", 1.0}});
  EXPECT_TRUE(slurp(nominal.dir / "rom.csv") != slurp(roll.dir / "rom.csv"));
}

TEST(IndependentEffects, EveryFormMovesTheData) {
  for (const auto& f : effect_forms()) {
    if (f.name == "none") continue;
    const EffectRun r = run("form_" + f.name, 8, {{f.name, 1.0}});
    EXPECT_GT(r.truth.magnitude_noise_units, 1.5) << f.name;
    ASSERT_EQ(r.truth.labels.size(), 1u);
    EXPECT_EQ(r.truth.labels[0], f.label);
    const auto truth = read_json(r.dir / "truth.json");
    EXPECT_EQ(truth.at("effects").at(0).at("form"), f.name);
    EXPECT_FALSE(truth.at("effects").at(0).at("parameters").empty()) << f.name;
  }
}

TEST(IndependentEffects, MagnitudeGrowsWithLevel) {
  for (const auto* form : {"strap_linear_preload", "dahl_friction", "slow_vent", "fabric_creep"}) {
    double previous = 0.0;
    for (const double level : {0.1, 0.4, 1.0}) {
      const EffectRun r = run(std::string("level_") + form, 9, {{form, level}});
      EXPECT_GT(r.truth.magnitude_noise_units, previous) << form << " " << level;
      previous = r.truth.magnitude_noise_units;
    }
  }
}

TEST(IndependentEffects, NoneCarriesVariationButNoGapAndTwoEffectsBothAct) {
  const EffectRun none = run("none", 10, {});
  EXPECT_EQ(none.truth.labels, std::vector<std::string>{"none"});
  EXPECT_EQ(none.truth.magnitude_noise_units, 0.0);
  double max_ratio = 0.0;
  for (const auto& f : none.truth.files) {
    EXPECT_GT(f.noise_sd, 0.0) << f.csv;
    max_ratio = std::max(max_ratio, f.effect_rms);
  }
  EXPECT_EQ(max_ratio, 0.0);
  const auto truth = read_json(none.dir / "truth.json");
  EXPECT_FALSE(truth.at("device_variation").empty());

  const EffectRun both = run("both", 10, {{"leaking_fitting", 1.0}, {"exponential_limits", 1.0}});
  EXPECT_EQ(both.truth.labels, (std::vector<std::string>{"outside:leaking_fitting", "passive_wrist"}));
  const EffectRun leak = run("leak_only", 10, {{"leaking_fitting", 1.0}});
  const EffectRun limits = run("limits_only", 10, {{"exponential_limits", 1.0}});
  // The leak shows in the tensile test (the passive wrist cannot); the passive wrist in the range of motion.
  EXPECT_TRUE(slurp(both.dir / "tensile.csv") == slurp(leak.dir / "tensile.csv"));
  EXPECT_TRUE(slurp(both.dir / "tensile.csv") != slurp(none.dir / "tensile.csv"));
  EXPECT_TRUE(slurp(both.dir / "rom.csv") != slurp(leak.dir / "rom.csv"));
  EXPECT_TRUE(slurp(both.dir / "rom.csv") != slurp(limits.dir / "rom.csv"));
  double max_file = 0.0;
  for (const auto& f : both.truth.files)
    max_file = std::max(max_file, f.noise_sd > 0 ? f.effect_rms / f.noise_sd : 0.0);
  EXPECT_DOUBLE_EQ(both.truth.magnitude_noise_units, max_file);
}

}  // namespace
}  // namespace softwrist::independent
