#pragma once
// Draws wrist poses of one device: its generated model with the fPAM plugin, posed by angles and pressures, rendered
// offscreen with each muscle coloured by its pressure. One per thread (it owns an OSMesa context).

#include "experiments/simulated_device.h"
#include "report/offscreen_renderer.h"
#include "report/run_moments.h"
#include "sim/wrist_sim.h"

namespace softwrist::report {

class PoseRenderer {
 public:
  // Throws std::runtime_error as OffscreenRenderer does (OSMesa missing, a size out of range).
  PoseRenderer(const sim::DeviceDescription& device, int width, int height, const RenderQuality& quality = {});

  // Throws std::runtime_error when a pressure is outside the device's regulator range or an angle is not finite. The
  // image is overwritten by the next call (OffscreenRenderer::Render).
  const Image& Render(const WristPose& pose, View view);

 private:
  experiments::SimulatedDevice device_;
  sim::WristSim wrist_;
  OffscreenRenderer renderer_;
  double max_pressure_kpa_;
};

}  // namespace softwrist::report
