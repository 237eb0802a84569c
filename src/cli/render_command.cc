#include "cli/render_command.h"

#include <memory>

#include <fmt/format.h>

#include "cli/arguments.h"
#include "physics/units.h"
#include "report/offscreen_renderer.h"
#include "sim/device.h"
#include "sim/model_builder.h"

namespace softwrist::cli {
namespace {

struct RenderOptions {
  std::string placement;
  double fe_deg = 0.0;
  double ur_deg = 0.0;
  std::string pressures_kpa = "0,0,0,0";
  std::string view = "radial";
  int width = 640;
  int height = 480;
  std::string out;
};

int run_render(const RenderOptions& options, std::ostream& out) {
  const sim::DeviceDescription device =
      options.placement.empty() ? sim::paper_device() : sim::load_device(options.placement);
  const auto pressures = parse_numbers(options.pressures_kpa, 4, "--pressures-kpa");
  const double max_kpa = units::pa_to_kpa(device.regulator.max_pressure);
  for (const double p : pressures) {
    if (p < 0.0 || p > max_kpa) {
      throw UsageError(fmt::format("--pressures-kpa: {} is outside the regulator's [0, {}] kPa", p, max_kpa));
    }
  }
  const sim::Model model = sim::Model::FromXml(sim::build_model_xml(device), sim::PluginSet::Default());
  const sim::Data data = sim::make_data(model);
  data->qpos[model->jnt_qposadr[model.id(mjOBJ_JOINT, "wrist_fe")]] = units::deg_to_rad(options.fe_deg);
  data->qpos[model->jnt_qposadr[model.id(mjOBJ_JOINT, "wrist_ur")]] = units::deg_to_rad(options.ur_deg);
  for (int i = 0; i < 4; ++i) {
    data->ctrl[i] = pressures[static_cast<std::size_t>(i)];
    data->act[i] = pressures[static_cast<std::size_t>(i)];
  }
  mj_forward(model.get(), data.get());
  report::OffscreenRenderer renderer(model, options.width, options.height);
  const auto view = options.view == "palmar" ? report::View::kPalmar : report::View::kRadial;
  report::write_png(renderer.Render(data.get(), view, max_kpa), options.out);
  out << fmt::format("Wrote {} ({}x{}, {} view)\n", options.out, options.width, options.height, options.view);
  return 0;
}

}  // namespace

void add_render_command(CLI::App& app, std::ostream& out) {
  auto options = std::make_shared<RenderOptions>();
  auto* render = app.add_subcommand("render", "Render the wrist model offscreen (OSMesa) to a PNG, each muscle "
                                              "coloured by its pressure (blue 0, red max)");
  render->add_option("--placement", options->placement, "Placement file; default: the paper's device")
      ->check(CLI::ExistingFile);
  render->add_option("--fe-deg", options->fe_deg, "Flexion (+) / extension (-) angle [deg]");
  render->add_option("--ur-deg", options->ur_deg, "Ulnar (+) / radial (-) deviation angle [deg]");
  render->add_option("--pressures-kpa", options->pressures_kpa, "flexor,extensor,ulnar,radial pressures [kPa]");
  render->add_option("--view", options->view, "radial (flexion/extension) or palmar (ulnar/radial)")
      ->check(CLI::IsMember({"radial", "palmar"}));
  render->add_option("--width", options->width, "Image width [px]")->check(CLI::Range(16, 1280));
  render->add_option("--height", options->height, "Image height [px]")->check(CLI::Range(16, 960));
  render->add_option("--out", options->out, "Output PNG")->required();
  render->callback([options, &out] { run_render(*options, out); });
}

}  // namespace softwrist::cli
