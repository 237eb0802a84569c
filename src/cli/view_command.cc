#include "cli/view_command.h"

#include <memory>

#include <fmt/format.h>

#include "cli/arguments.h"
#include "physics/units.h"
#include "sim/device.h"
#include "sim/model_builder.h"
#include "viewer/interactive_viewer.h"

namespace softwrist::cli {
namespace {

struct ViewOptions {
  std::string model_file;
  std::string placement;
  std::string pressures_kpa;
  int frames = 0;
  std::string screenshot;
  int width = 1200, height = 800;
};

void run_view(const ViewOptions& options, std::ostream& out) {
  if (!options.screenshot.empty() && options.frames == 0) throw UsageError("--screenshot needs --frames N");
  const sim::PluginSet plugins = sim::PluginSet::Default();
  const sim::DeviceDescription device =
      options.placement.empty() ? sim::paper_device() : sim::load_device(options.placement);
  const sim::Model model = options.model_file.empty()
                               ? sim::Model::FromXml(sim::build_model_xml(device), plugins, "the generated model")
                               : sim::Model::FromFile(options.model_file, plugins);
  viewer::ViewerOptions viewer{.width = options.width,
                               .height = options.height,
                               .frames = options.frames,
                               .screenshot = options.screenshot,
                               .default_max_kpa = units::pa_to_kpa(device.regulator.max_pressure)};
  if (!options.pressures_kpa.empty()) {
    const auto pressures = parse_numbers(options.pressures_kpa, static_cast<std::size_t>(model->nu), "--pressures-kpa");
    for (std::size_t i = 0; i < pressures.size(); ++i) {
      if (pressures[i] < 0.0 || pressures[i] > viewer.default_max_kpa) {
        throw UsageError(
            fmt::format("--pressures-kpa: {} is outside [0, {}] kPa", pressures[i], viewer.default_max_kpa));
      }
      viewer.initial_commands_kpa[static_cast<int>(i)] = pressures[i];
    }
  }
  const viewer::ViewerSummary summary = viewer::run_viewer(model, viewer);
  out << fmt::format("{} frames, {:.2f} s simulated\n{}", summary.frames, summary.simulated_s, summary.final_state);
  if (!options.screenshot.empty()) out << fmt::format("Wrote {}\n", options.screenshot);
}

}  // namespace

void add_view_command(CLI::App& app, std::ostream& out) {
  auto options = std::make_shared<ViewOptions>();
  auto* view = app.add_subcommand(
      "view",
      "Interactive viewer (GLFW): drag to orbit, 1-9 select a muscle, Up/Down its pressure, 0 vent, Space "
      "pause, Backspace reset, V view, Esc quit");
  auto* model = view->add_option("model", options->model_file,
                                 "An MJCF model (default: the generated model of the "
                                 "paper's device, or of --placement)")
                    ->check(CLI::ExistingFile);
  view->add_option("--placement", options->placement, "Placement file whose generated model to view")
      ->check(CLI::ExistingFile)
      ->excludes(model);
  view->add_option("--pressures-kpa", options->pressures_kpa, "Initial commanded pressures, one per actuator [kPa]");
  view->add_option("--frames", options->frames, "Stop after N frames of 1/60 s simulated time (scripted runs)")
      ->check(CLI::Range(1, 100000));
  view->add_option("--screenshot", options->screenshot, "PNG of the last frame (with --frames)");
  view->add_option("--width", options->width, "Window width [px]")->check(CLI::Range(320, 3840));
  view->add_option("--height", options->height, "Window height [px]")->check(CLI::Range(240, 2160));
  view->callback([options, &out] { run_view(*options, out); });
}

}  // namespace softwrist::cli
