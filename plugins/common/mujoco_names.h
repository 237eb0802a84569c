#pragma once
// Names of MuJoCo objects as errors print them, shared by the plugins' adapters and the sim layer that loads them.

#include <string>

#include <mujoco/mujoco.h>

namespace softwrist::plugin {

// The actuator's name, or "#ID" for an unnamed one.
inline std::string actuator_name(const mjModel* m, int id) {
  const char* name = mj_id2name(m, mjOBJ_ACTUATOR, id);
  return name != nullptr ? name : "#" + std::to_string(id);
}

}  // namespace softwrist::plugin
