#include "report/pose_renderer.h"

#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "physics/units.h"

namespace softwrist::report {

PoseRenderer::PoseRenderer(const sim::DeviceDescription& device, int width, int height, const RenderQuality& quality)
    : device_(device),
      wrist_(device_.model),
      renderer_(device_.model, width, height, quality),
      max_pressure_kpa_(units::pa_to_kpa(device.regulator.max_pressure)) {}

const Image& PoseRenderer::Render(const WristPose& pose, View view) {
  if (!std::isfinite(pose.fe) || !std::isfinite(pose.ur)) throw std::runtime_error("render: wrist angle is not finite");
  for (std::size_t i = 0; i < 4; ++i) {
    const double p = pose.pressures_kpa[i];
    if (!(p >= 0.0 && p <= max_pressure_kpa_)) {
      throw std::runtime_error(fmt::format("render: {} pressure {} kPa is outside the regulator's [0, {}] kPa",
                                           sim::kMuscleNames[i], p, max_pressure_kpa_));
    }
  }
  wrist_.set_pose(pose.fe, pose.ur, pose.pressures_kpa);
  return renderer_.Render(wrist_.data(), view, max_pressure_kpa_);
}

}  // namespace softwrist::report
