#include "cli/model_commands.h"

#include <array>
#include <filesystem>
#include <fstream>
#include <memory>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "cli/arguments.h"
#include "physics/exosuit_layout.h"
#include "physics/paper_parameters.h"
#include "physics/range_of_motion.h"
#include "physics/units.h"
#include "sim/device.h"
#include "sim/model.h"
#include "sim/model_builder.h"

namespace softwrist::cli {
namespace {

namespace physics = softwrist::physics;
namespace paper = softwrist::physics::paper;
using nlohmann::json;
using units::cm_to_m;
using units::deg_to_rad;
using units::kpa_to_pa;
using units::m_to_cm;
using units::rad_to_deg;

// Section Parameter optimization: 448 kPa is the burst pressure of the r0 = 1.23 cm fPAM; no model query above it
// describes a real muscle.
constexpr double kMaxModelPressureKpa = 448.0;

double checked_pressure_pa(double pressure_kpa) {
  if (!std::isfinite(pressure_kpa) || pressure_kpa < 0.0 || pressure_kpa > kMaxModelPressureKpa) {
    throw UsageError(fmt::format("--pressure-kpa: {} is outside [0, {}] kPa (the fPAM's burst pressure)", pressure_kpa,
                                 kMaxModelPressureKpa));
  }
  return kpa_to_pa(pressure_kpa);
}

// --- fPAM and stretch options shared by the model subcommands ----------------------------------------------------

struct FpamOptions {
  std::string table;
  double r0_cm = 0.0;
  double eps_max = 0.0;
  CLI::Option* r0 = nullptr;
  CLI::Option* eps = nullptr;
};

void add_fpam_options(CLI::App& command, FpamOptions& options, const std::string& default_description) {
  options.r0 = command.add_option("--r0", options.r0_cm, "Constant fully stretched fPAM radius r0 [cm]");
  options.eps = command.add_option("--eps-max", options.eps_max, "Constant maximum contraction ratio eps_max");
  options.r0->needs(options.eps);
  options.eps->needs(options.r0);
  command
      .add_option("--fpam-table", options.table,
                  "Per-pressure fPAM parameters: 'tensile' = Table tensile_testing_parameters (default: " +
                      default_description + ")")
      ->check(CLI::IsMember({"tensile"}))
      ->excludes(options.r0)
      ->excludes(options.eps);
}

physics::FpamParameters build_fpam(const FpamOptions& options, const physics::FpamParameters& fallback) {
  if (options.table == "tensile") return paper::tensile_fpam();
  if (options.r0 != nullptr && options.r0->count() > 0)
    return physics::FpamParameters::Constant(cm_to_m(options.r0_cm), options.eps_max);
  return fallback;
}

std::string describe(const physics::FpamParameters& fpam) {
  if (!fpam.is_constant()) return fmt::format("per-pressure table ({} rows)", fpam.rows().size());
  const auto& row = fpam.rows().front();
  return fmt::format("r0={:.3f} cm eps_max={:.3f}", m_to_cm(row.radius), row.max_contraction);
}

struct StretchOptions {
  std::string mode = "none";
  double k1_n_per_cm2 = -43.36;  // Table torque_measurement_parameters
  double k2_n_per_cm2 = -1097.50;
};

void add_stretch_options(CLI::App& command, StretchOptions& options) {
  command
      .add_option("--stretch", options.mode,
                  "Mounting-point stretching: none, oneshot (the paper's) or "
                  "selfconsistent (Eqn. fabric_stretching)")
      ->check(CLI::IsMember({"none", "oneshot", "selfconsistent"}));
  command.add_option("--K1", options.k1_n_per_cm2, "Forearm mount stiffness K1 [N/cm^2]; only |K1| is used");
  command.add_option("--K2", options.k2_n_per_cm2, "Hand mount stiffness K2 [N/cm^2]; only |K2| is used");
}

void apply_stretch(const StretchOptions& options, physics::Muscle& muscle) {
  muscle.stretch_mode = *physics::parse_stretch_mode(options.mode);  // CLI11 checked the name
  muscle.mount_stiffness = {units::n_per_cm2_to_n_per_m2(options.k1_n_per_cm2),
                            units::n_per_cm2_to_n_per_m2(options.k2_n_per_cm2)};
}

physics::Placement parse_placement_cm(const std::string& text, std::string_view option) {
  const auto v = parse_numbers(text, 4, option);
  return {cm_to_m(v[0]), cm_to_m(v[1]), cm_to_m(v[2]), cm_to_m(v[3])};
}

// --- model torque ------------------------------------------------------------------------------------------------

struct TorqueOptions {
  double pressure_kpa = physics::kRegulatorMaxPressureKpa;
  std::string angles = "-67.5:90:22.5";
  std::string placement = "19.47,4.93,8.30,3.38";
  double l0_cm = 32.0;
  double l0_angle_deg = 0.0;
  CLI::Option* l0_angle = nullptr;
  double rw_cm = 3.99;
  FpamOptions fpam;
  StretchOptions stretch;
  bool json = false;
};

int run_torque(const TorqueOptions& options, std::ostream& out) {
  const double pressure = checked_pressure_pa(options.pressure_kpa);
  const auto angles_deg = parse_angle_range_deg(options.angles, "--angles");
  // What can throw (a bad option) is read before the muscle is built: GCC 12 destroys a member twice when an
  // exception leaves the aggregate initialisation of a class with a base (here MuscleLaw).
  const physics::Placement placement = parse_placement_cm(options.placement, "--placement");
  physics::FpamParameters fpam = build_fpam(options.fpam, paper::tensile_fpam());
  physics::Muscle muscle{
      {.fpam = std::move(fpam), .rest_length = cm_to_m(options.l0_cm)}, placement, cm_to_m(options.rw_cm)};
  if (options.l0_angle->count() > 0) {
    muscle.rest_length =
        physics::rest_length_for_range(muscle.placement, muscle.wrist_radius, deg_to_rad(options.l0_angle_deg));
  }
  apply_stretch(options.stretch, muscle);
  physics::validate(muscle);

  json result = {{"angles_deg", json::array()},
                 {"torque_nm", json::array()},
                 {"regime", json::array()},
                 {"force_n", json::array()},
                 {"length_cm", json::array()}};
  std::string table =
      fmt::format("{:>10} {:>10} {:>9} {:>10} {:>9}\n", "angle_deg", "torque_nm", "force_n", "length_cm", "regime");
  for (const double angle_deg : angles_deg) {
    const auto state = physics::muscle_state(muscle, deg_to_rad(angle_deg), pressure);
    result["angles_deg"].push_back(angle_deg);
    result["torque_nm"].push_back(state.torque);
    result["regime"].push_back(physics::to_string(state.regime));
    result["force_n"].push_back(state.force);
    result["length_cm"].push_back(m_to_cm(state.effective_length));
    table += fmt::format("{:>10.3f} {:>10.4f} {:>9.3f} {:>10.3f} {:>9}\n", angle_deg, state.torque, state.force,
                         m_to_cm(state.effective_length), physics::to_string(state.regime));
  }
  if (options.json) {
    out << result.dump() << '\n';
  } else {
    const auto& p = muscle.placement;
    out << fmt::format(
               "# fPAM torque at {} kPa: d1={:.2f} w1={:.2f} d2={:.2f} w2={:.2f} L0={:.2f} r_w={:.2f} cm, "
               "{}, stretch {}\n",
               options.pressure_kpa, m_to_cm(p.d1), m_to_cm(p.w1), m_to_cm(p.d2), m_to_cm(p.w2),
               m_to_cm(muscle.rest_length), m_to_cm(muscle.wrist_radius), describe(muscle.fpam), options.stretch.mode)
        << table;
  }
  return 0;
}

// --- model rom ---------------------------------------------------------------------------------------------------

struct RomOptions {
  double pressure_kpa = physics::kRegulatorMaxPressureKpa;
  double rw_cm = units::m_to_cm(paper::kRomWristRadius);
  FpamOptions fpam;
  StretchOptions stretch;
  std::array<std::string, 4> overrides;  // per direction "d1,w1,d2,w2,L0" [cm]
  bool json = false;
};

struct RomRow {
  const paper::RomEntry* entry;
  std::optional<double> limit_deg;
  // The eps_max that would put this muscle's limit at the paper's modeled limit: 1 - L(paper limit) / L0.
  double eps_max_matching_paper;
};

std::vector<RomRow> modeled_limits(const RomOptions& options) {
  const double pressure = checked_pressure_pa(options.pressure_kpa);
  std::vector<RomRow> rows;
  for (std::size_t i = 0; i < paper::rom_table().size(); ++i) {
    const auto& entry = paper::rom_table()[i];
    physics::Muscle muscle = paper::rom_muscle(entry);
    muscle.wrist_radius = cm_to_m(options.rw_cm);
    muscle.fpam = build_fpam(options.fpam, paper::rom_fpam());
    if (!options.overrides[i].empty()) {
      const std::string option = fmt::format("--{}", entry.direction);
      const auto v = parse_numbers(options.overrides[i], 5, option);
      muscle.placement = {cm_to_m(v[0]), cm_to_m(v[1]), cm_to_m(v[2]), cm_to_m(v[3])};
      muscle.rest_length = cm_to_m(v[4]);
    }
    apply_stretch(options.stretch, muscle);
    physics::validate(muscle);
    const auto limit = physics::joint_limit(muscle, pressure, std::numbers::pi / 2.0);
    const double paper_length =
        physics::muscle_path(muscle.placement, muscle.wrist_radius, deg_to_rad(entry.paper_modeled_limit_deg())).length;
    rows.push_back({&entry, limit ? std::optional<double>(rad_to_deg(*limit)) : std::nullopt,
                    1.0 - paper_length / muscle.rest_length});
  }
  return rows;
}

json rom_json(const std::vector<RomRow>& rows, double pressure_kpa) {
  json result = {{"pressure_kpa", pressure_kpa}};
  json paper_modeled, paper_exosuit, biological, matching;
  for (const auto& row : rows) {
    const std::string direction(row.entry->direction);
    result[direction + "_deg"] = row.limit_deg ? json(*row.limit_deg) : json(nullptr);
    paper_modeled[direction + "_deg"] = row.entry->paper_modeled_limit_deg();
    paper_exosuit[direction + "_deg"] = row.entry->exosuit_deg;
    biological[direction + "_deg"] = row.entry->biological_deg;
    matching[direction] = row.eps_max_matching_paper;
  }
  result["paper_modeled_deg"] = paper_modeled;
  result["paper_measured_exosuit_deg"] = paper_exosuit;
  result["paper_biological_deg"] = biological;
  result["eps_max_matching_paper"] = matching;
  return result;
}

std::string rom_markdown(const std::vector<RomRow>& rows) {
  std::string text =
      "| direction | modeled limit (softwrist) | paper's modeled limit (measured + error) | difference | "
      "eps_max matching the paper's limit | measured exosuit (paper) | biological (paper) |\n"
      "|---|---|---|---|---|---|---|\n";
  for (const auto& row : rows) {
    const auto& e = *row.entry;
    const std::string mine = row.limit_deg ? fmt::format("{:.1f} deg", *row.limit_deg) : "beyond 90 deg";
    const std::string diff =
        row.limit_deg ? fmt::format("{:+.1f} deg", *row.limit_deg - e.paper_modeled_limit_deg()) : "-";
    text += fmt::format("| {} | {} | {:.1f} deg | {} | {:.3f} | {:.1f} (STD {:.1f}) deg | {:.1f} (STD {:.1f}) deg |\n",
                        e.direction, mine, e.paper_modeled_limit_deg(), diff, row.eps_max_matching_paper, e.exosuit_deg,
                        e.exosuit_std_deg, e.biological_deg, e.biological_std_deg);
  }
  return text;
}

int run_rom(const RomOptions& options, std::ostream& out) {
  const auto rows = modeled_limits(options);
  if (options.json) {
    out << rom_json(rows, options.pressure_kpa).dump() << '\n';
  } else {
    out << fmt::format("# Modeled range of motion at {} kPa (Table RoM placements)\n", options.pressure_kpa)
        << rom_markdown(rows);
  }
  return 0;
}

// --- model tables: the main job's torque and range-of-motion tables ----------------------------------------------

std::string torque_markdown(const physics::Muscle& muscle, const std::vector<double>& angles_deg, json& record) {
  std::string text = "| angle [deg] |";
  for (const double p : paper::kMeasurementPressures) text += fmt::format(" {:.0f} kPa |", units::pa_to_kpa(p));
  text += "\n|---|";
  for (std::size_t i = 0; i < paper::kMeasurementPressures.size(); ++i) text += "---|";
  text += "\n";
  for (const double angle_deg : angles_deg) {
    text += fmt::format("| {:.1f} |", angle_deg);
    json row = {{"angle_deg", angle_deg}, {"torque_nm", json::array()}};
    for (const double p : paper::kMeasurementPressures) {
      const double torque = physics::muscle_state(muscle, deg_to_rad(angle_deg), p).torque;
      text += fmt::format(" {:.3f} |", torque);
      row["torque_nm"].push_back(torque);
    }
    record.push_back(row);
    text += "\n";
  }
  return text;
}

void write_file(const std::filesystem::path& path, const std::string& text) {
  std::ofstream file(path);
  file << text;
  if (!file) throw std::runtime_error(fmt::format("cannot write {}", path.string()));
}

int run_tables(const std::string& out_dir, std::ostream& out) {
  const std::filesystem::path dir(out_dir);
  std::error_code error;
  std::filesystem::create_directories(dir, error);
  if (error) throw std::runtime_error(fmt::format("cannot create {}: {}", dir.string(), error.message()));

  const std::vector<double> angles_deg = {-67.5, -45.0, -22.5, 0.0, 22.5, 45.0, 67.5, 90.0};
  json torque_record = {{"pressures_kpa", json::array()}, {"models", json::object()}};
  for (const double p : paper::kMeasurementPressures) torque_record["pressures_kpa"].push_back(units::pa_to_kpa(p));
  std::string markdown =
      "# softwrist model tables\n\n## Flexor torque [N m], Table torque_measurement_parameters device\n\n"
      "Angles of Section Torque applied by the exosuit; flexion positive.\n";
  const std::array<std::pair<physics::StretchMode, const char*>, 3> models = {{
      {physics::StretchMode::kNone, "fixed placement, no stretching (the paper's third method)"},
      {physics::StretchMode::kOneShot, "fixed placement with one-shot stretching (the paper's second method)"},
      {physics::StretchMode::kSelfConsistent, "fixed placement with self-consistent stretching"},
  }};
  for (const auto& [mode, title] : models) {
    json record = json::array();
    markdown += fmt::format("\n### {}\n\n", title) +
                torque_markdown(paper::torque_measurement_flexor(mode), angles_deg, record);
    torque_record["models"][physics::to_string(mode)] = record;
  }
  const auto rom_rows = modeled_limits(RomOptions{});
  markdown += "\n## Range of motion at 137 kPa, Table RoM placements\n\n" + rom_markdown(rom_rows);

  write_file(dir / "model_tables.md", markdown);
  write_file(dir / "torque.json", torque_record.dump(2) + "\n");
  write_file(dir / "rom.json", rom_json(rom_rows, physics::kRegulatorMaxPressureKpa).dump(2) + "\n");
  out << markdown << fmt::format("\nWrote {}/model_tables.md, torque.json, rom.json\n", dir.string());
  return 0;
}

// --- model build / placement: the MuJoCo model from a placement file ------------------------------------------

struct BuildOptions {
  std::string placement;  // empty: the paper's device
  std::string out;
};

int run_build(const BuildOptions& options, std::ostream& out) {
  const sim::DeviceDescription device =
      options.placement.empty() ? sim::paper_device() : sim::load_device(options.placement);
  const std::string xml = sim::build_model_xml(device);
  // Load it once with the plugins, so a model that would not load is never written.
  sim::Model::FromXml(xml, sim::PluginSet::Default(), options.out);
  write_file(options.out, xml);
  out << fmt::format("Wrote {} ({} muscles, plugin softwrist.fpam)\n", options.out, sim::kMuscleNames.size());
  return 0;
}

}  // namespace

void add_model_commands(CLI::App& app, std::ostream& out) {
  auto* model = app.add_subcommand("model", "The paper's analytic model: torque curves, range of motion, tables");
  model->require_subcommand(1);

  auto torque_options = std::make_shared<TorqueOptions>();
  auto* torque = model->add_subcommand("torque",
                                       "Torque of one fPAM over a range of wrist angles (Eqns. force, "
                                       "tau1, tau2, fabric_stretching). Defaults: the flexor of Table "
                                       "torque_measurement_parameters");
  torque->add_option("--pressure-kpa", torque_options->pressure_kpa, "fPAM pressure [kPa]");
  torque->add_option("--angles", torque_options->angles, "Wrist angles FROM:TO:STEP [deg], flexion positive");
  torque->add_option("--placement", torque_options->placement, "Mounting points d1,w1,d2,w2 [cm]");
  auto* l0 = torque->add_option("--L0", torque_options->l0_cm, "Fully stretched fPAM length L0 [cm]");
  torque_options->l0_angle =
      torque
          ->add_option("--L0-from-angle", torque_options->l0_angle_deg,
                       "Instead of --L0: L0 = Eqn. length at this wrist angle [deg] (e.g. -65.4)")
          ->excludes(l0);
  torque->add_option("--rw", torque_options->rw_cm, "Wrist radius r_w [cm]");
  add_fpam_options(*torque, torque_options->fpam, "tensile");
  add_stretch_options(*torque, torque_options->stretch);
  torque->add_flag("--json", torque_options->json, "Print JSON {angles_deg, torque_nm, regime, force_n, length_cm}");
  torque->callback([torque_options, &out] { run_torque(*torque_options, out); });

  auto rom_options = std::make_shared<RomOptions>();
  auto* rom = model->add_subcommand("rom",
                                    "Modeled joint limits (angle where the torque reaches zero) of the four "
                                    "muscles of Table RoM, beside the paper's");
  rom->add_option("--pressure-kpa", rom_options->pressure_kpa, "fPAM pressure [kPa]");
  rom->add_option("--rw", rom_options->rw_cm, "Wrist radius r_w [cm] (Table RoM gives none)");
  add_fpam_options(*rom, rom_options->fpam, "r0=1.26 cm, eps_max=0.277: Table tensile_testing_parameters at 137 kPa");
  add_stretch_options(*rom, rom_options->stretch);
  for (std::size_t i = 0; i < paper::rom_table().size(); ++i) {
    const std::string direction(paper::rom_table()[i].direction);
    rom->add_option("--" + direction, rom_options->overrides[i],
                    "Override the " + direction + " muscle: d1,w1,d2,w2,L0 [cm]");
  }
  rom->add_flag("--json", rom_options->json, "Print JSON {flexion_deg, extension_deg, ulnar_deg, radial_deg, ...}");
  rom->callback([rom_options, &out] { run_rom(*rom_options, out); });

  auto tables_dir = std::make_shared<std::string>("out/model");
  auto* tables = model->add_subcommand("tables",
                                       "The main job's tables: flexor torque at the paper's angles and "
                                       "pressures (three models) and the modeled range of motion");
  tables->add_option("--out", *tables_dir, "Directory for model_tables.md, torque.json, rom.json");
  tables->callback([tables_dir, &out] { run_tables(*tables_dir, out); });

  auto build_options = std::make_shared<BuildOptions>();
  auto* build = model->add_subcommand("build",
                                      "Generate the MuJoCo hand-forearm model (MJCF) from a placement file "
                                      "(docs/placement-file.md); checks that it loads with the plugins");
  build->add_option("--placement", build_options->placement, "Placement file (JSON); default: the paper's device")
      ->check(CLI::ExistingFile);
  build->add_option("--out", build_options->out, "Output MJCF file")->required();
  build->callback([build_options, &out] { run_build(*build_options, out); });

  struct PlacementOptions {
    std::string out;
    std::string device = "paper";
  };
  auto placement_options = std::make_shared<PlacementOptions>();
  auto* placement = model->add_subcommand("placement",
                                          "Write one of the paper's devices as a placement file, a "
                                          "starting point for a personalised one");
  placement->add_option("--out", placement_options->out, "Output file; default: print");
  placement
      ->add_option("--device", placement_options->device,
                   "paper: the torque-rig flexor with the Table RoM muscles; rom: all four Table RoM muscles")
      ->check(CLI::IsMember({"paper", "rom"}));
  placement->callback([placement_options, &out] {
    const std::string text =
        sim::device_to_json(placement_options->device == "rom" ? sim::rom_device() : sim::paper_device());
    if (placement_options->out.empty()) {
      out << text;
    } else {
      write_file(placement_options->out, text);
    }
  });
}

}  // namespace softwrist::cli
