#include "report/scene_style.h"

#include <algorithm>
#include <string_view>

namespace softwrist::report {

std::string view_name(View view) { return view == View::kRadial ? "radial" : "palmar"; }

void set_view_camera(View view, mjvCamera* camera) {
  mjv_defaultCamera(camera);
  camera->type = mjCAMERA_FREE;
  camera->lookat[0] = -0.05;
  camera->distance = 0.56;
  camera->azimuth = view == View::kRadial ? 90.0 : -90.0;
  camera->elevation = view == View::kRadial ? -65.0 : -5.0;
}

void colour_muscles_by_pressure(const mjModel* model, const mjData* data, double max_pressure_kpa, mjvScene* scene) {
  for (int i = 0; i < scene->ngeom; ++i) {
    mjvGeom& geom = scene->geoms[i];
    if (geom.objtype != mjOBJ_TENDON) continue;
    // The tendon's fPAM acts on it, or (routing planar, sim/device.h) on its joint under the tendon's name.
    const char* tendon = mj_id2name(model, mjOBJ_TENDON, geom.objid);
    for (int u = 0; u < model->nu; ++u) {
      const bool on_tendon = model->actuator_trntype[u] == mjTRN_TENDON && model->actuator_trnid[2 * u] == geom.objid;
      const char* actuator = mj_id2name(model, mjOBJ_ACTUATOR, u);
      const bool named = tendon != nullptr && actuator != nullptr && std::string_view(tendon) == actuator;
      if (!on_tendon && !named) continue;
      const int act = u - (model->nu - model->na);  // activations belong to the last na actuators
      const double pressure = act >= 0 ? data->act[act] : data->ctrl[u];
      const float s = static_cast<float>(std::clamp(pressure / max_pressure_kpa, 0.0, 1.0));
      geom.rgba[0] = 0.15f + 0.8f * s;
      geom.rgba[1] = 0.25f * (1.0f - s);
      geom.rgba[2] = 0.9f * (1.0f - s);
      geom.rgba[3] = 1.0f;
      break;  // the tendon's first actuator is its fPAM; a hysteresis state after it is no pressure
    }
  }
}

}  // namespace softwrist::report
