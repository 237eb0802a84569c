#include "cli/bench_commands.h"

#include <algorithm>
#include <chrono>
#include <memory>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "cli/arguments.h"
#include "sim/device.h"
#include "sim/model.h"
#include "sim/model_builder.h"

namespace softwrist::cli {
namespace {

struct SimBenchOptions {
  int steps = 20000;
  int rounds = 7;
  bool json = false;
};

// Steps per second of `steps` steps from reset, with the muscles driven by a slow square wave so that the wrist
// moves through straight and wrapped configurations.
double steps_per_second(const sim::Model& model, mjData* d, int steps) {
  mj_resetData(model.get(), d);
  const auto start = std::chrono::steady_clock::now();
  for (int i = 0; i < steps; ++i) {
    const bool phase = (i / 1000) % 2 == 0;
    d->ctrl[0] = phase ? 120.0 : 15.0;
    d->ctrl[1] = phase ? 15.0 : 120.0;
    d->ctrl[2] = phase ? 80.0 : 20.0;
    d->ctrl[3] = phase ? 20.0 : 80.0;
    mj_step(model.get(), d);
  }
  const std::chrono::duration<double> elapsed = std::chrono::steady_clock::now() - start;
  return steps / elapsed.count();
}

int run_sim_bench(const SimBenchOptions& options, std::ostream& out) {
  if (options.steps < 100 || options.rounds < 1) throw UsageError("--steps must be >= 100 and --rounds >= 1");
  const sim::DeviceDescription device = sim::paper_device();
  const auto plugins = sim::PluginSet::Default();
  const sim::Model plugin = sim::Model::FromXml(sim::build_model_xml(device), plugins, "plugin model");
  const sim::Model builtin = sim::Model::FromXml(
      sim::build_model_xml(device, {.actuators = sim::ActuatorKind::kBuiltinGeneral}), plugins, "builtin model");
  const sim::Data plugin_data = sim::make_data(plugin), builtin_data = sim::make_data(builtin);
  // Interleaved rounds, best of each: the two are measured under the same machine load.
  double best_plugin = 0.0, best_builtin = 0.0;
  for (int round = 0; round < options.rounds; ++round) {
    best_plugin = std::max(best_plugin, steps_per_second(plugin, plugin_data.get(), options.steps));
    best_builtin = std::max(best_builtin, steps_per_second(builtin, builtin_data.get(), options.steps));
  }
  const double ratio = best_builtin / best_plugin;  // cost of the plugin relative to the built-in actuator
  if (options.json) {
    out << nlohmann::json{{"plugin_steps_per_s", best_plugin},
                          {"builtin_steps_per_s", best_builtin},
                          {"ratio", ratio},
                          {"steps", options.steps},
                          {"rounds", options.rounds},
                          {"stretch", physics::to_string(device.stretch_mode)}}
               .dump()
        << '\n';
  } else {
    out << fmt::format("4-muscle wrist model, {} steps x {} rounds (best), stretch {}\n", options.steps,
                       options.rounds, physics::to_string(device.stretch_mode))
        << fmt::format("  fPAM plugin        {:>10.0f} steps/s\n", best_plugin)
        << fmt::format("  built-in <general> {:>10.0f} steps/s\n", best_builtin)
        << fmt::format("  ratio (plugin cost / built-in cost) {:.3f}  (target <= 1.3)\n", ratio);
  }
  return 0;
}

}  // namespace

void add_bench_commands(CLI::App& app, std::ostream& out) {
  auto* bench = app.add_subcommand("bench", "Speed figures, compared side by side in one run");
  bench->require_subcommand(1);
  auto options = std::make_shared<SimBenchOptions>();
  auto* sim_bench = bench->add_subcommand("sim", "Steps per second of the model with the fPAM plugin and with "
                                                 "MuJoCo's built-in <general> tendon actuators, and their ratio");
  sim_bench->add_option("--steps", options->steps, "Steps per round");
  sim_bench->add_option("--rounds", options->rounds, "Interleaved rounds; the best of each is reported");
  sim_bench->add_flag("--json", options->json, "Print {plugin_steps_per_s, builtin_steps_per_s, ratio, ...}");
  sim_bench->callback([options, &out] { run_sim_bench(*options, out); });
}

}  // namespace softwrist::cli
