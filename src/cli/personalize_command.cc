#include "cli/personalize_command.h"

#include <fstream>
#include <memory>

#include <fmt/format.h>

#include "cli/arguments.h"
#include "optimize/personalize.h"
#include "physics/units.h"
#include "sim/device.h"
#include "sim/model_builder.h"

namespace softwrist::cli {
namespace {

using units::m_to_cm;

struct PersonalizeOptions {
  std::string user;
  std::string out;
  int jobs = 2;
};

void write_text(const std::filesystem::path& path, const std::string& text) {
  std::ofstream file(path);
  file << text;
  if (!file) throw std::runtime_error(path.string() + ": cannot write");
}

void run_personalize(const PersonalizeOptions& options, std::ostream& out) {
  if (options.jobs < 1) throw UsageError("--jobs must be >= 1");
  const optimize::UserDescription user = optimize::load_user(options.user);
  optimize::OptimizerOptions optimizer;
  optimizer.jobs = options.jobs;
  const auto muscles = optimize::personalize(user, optimizer);

  sim::DeviceDescription device{.muscles = {}, .fpam = user.fpam};
  for (std::size_t i = 0; i < 4; ++i) {
    const auto& m = muscles[i].muscle;
    device.muscles[i] = {m.placement, m.rest_length, m.wrist_radius};
  }
  device.regulator.max_pressure = user.pressure_limit;
  device.wrist.flexion_limit = user.range[0];
  device.wrist.extension_limit = user.range[1];
  device.wrist.ulnar_limit = user.range[2];
  device.wrist.radial_limit = user.range[3];

  const std::filesystem::path dir = options.out.empty()
                                        ? std::filesystem::path("runs") / std::filesystem::path(options.user).stem()
                                        : std::filesystem::path(options.out);
  std::filesystem::create_directories(dir);
  write_text(dir / "placement.json", sim::device_to_json(device));
  write_text(dir / "model.xml", sim::build_model_xml(device));

  out << fmt::format("{}: {:.0f} kPa, r0 {:.2f} cm, eps_max {:.3f}\n", user.name, units::pa_to_kpa(user.pressure_limit),
                     m_to_cm(user.fpam.at_pressure(user.pressure_limit).radius),
                     user.fpam.at_pressure(user.pressure_limit).max_contraction)
      << "  muscle     d1_cm  w1_cm  d2_cm  w2_cm  L0_cm  r_w_cm  objective_nm  max_deficit_nm\n";
  for (std::size_t i = 0; i < 4; ++i) {
    const auto& m = muscles[i];
    const auto& p = m.muscle.placement;
    out << fmt::format("  {:<9} {:6.2f} {:6.2f} {:6.2f} {:6.2f} {:6.2f} {:7.2f} {:13.4f} {:15.4f}\n",
                       sim::kMuscleNames[i], m_to_cm(p.d1), m_to_cm(p.w1), m_to_cm(p.d2), m_to_cm(p.w2),
                       m_to_cm(m.muscle.rest_length), m_to_cm(m.muscle.wrist_radius), m.objective, m.max_deficit);
  }
  out << fmt::format("wrote {} and {}\n", (dir / "placement.json").string(), (dir / "model.xml").string());
}

}  // namespace

void add_personalize_command(CLI::App& app, std::ostream& out) {
  auto options = std::make_shared<PersonalizeOptions>();
  auto* command =
      app.add_subcommand("personalize",
                         "Optimize all four fPAMs' placement for one user (arm dimensions, reference torques, pressure "
                         "limit) and write the placement file and MuJoCo model (docs/personalize.md)");
  command->add_option("--user", options->user, "User file (JSON, softwrist.user/1)")
      ->required()
      ->check(CLI::ExistingFile);
  command->add_option("--out", options->out, "Output directory; default runs/<user file name>");
  command->add_option("--jobs", options->jobs, "Threads");
  command->callback([options, &out] { run_personalize(*options, out); });
}

}  // namespace softwrist::cli
