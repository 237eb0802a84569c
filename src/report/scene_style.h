#pragma once
// How softwrist draws the wrist, offscreen and in the viewer alike: the paper's two cameras and each muscle
// coloured by its pressure.

#include <string>

#include <mujoco/mujoco.h>

namespace softwrist::report {

// The paper's figure views (Fig. Overview): radial for flexion/extension, palmar for ulnar/radial deviation.
enum class View { kRadial, kPalmar };

std::string view_name(View view);  // "radial", "palmar"

// Puts a free camera at the view: the flexion/extension axis is vertical, so the radial view looks down it; the
// palmar view looks along ulnar/radial deviation's axis at the palm.
void set_view_camera(View view, mjvCamera* camera);

// Colours each tendon that an actuator pulls by that actuator's pressure (its activation when it has one, else its
// control), from blue at 0 to red at `max_pressure_kpa`. Call after mjv_updateScene.
void colour_muscles_by_pressure(const mjModel* model, const mjData* data, double max_pressure_kpa, mjvScene* scene);

}  // namespace softwrist::report
