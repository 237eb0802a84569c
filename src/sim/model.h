#pragma once
// A MuJoCo model loaded with its plugins attached, and its data, as RAII handles.

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <mujoco/mujoco.h>

#include "sim/plugins.h"

namespace softwrist::sim {

class Model {
 public:
  // Loads MJCF, then checks that every actuator with user dynamics, gain or bias has a plugin configuration naming
  // a loaded plugin, and attaches the plugins. Throws std::runtime_error naming the source, the actuator and the
  // problem (a malformed MJCF, an unknown plugin name, an invalid attribute).
  static Model FromXml(const std::string& xml, const PluginSet& plugins, const std::string& source_name = "model.xml");
  static Model FromFile(const std::filesystem::path& path, const PluginSet& plugins);

  // A copy of the model with the plugins attached to it: for a simulation that changes its model as it goes (WristSim
  // moving a non-circular wrist surface's equivalent circles), which must not share it with other threads.
  Model Copy() const;

  const mjModel* get() const { return model_.get(); }
  // The model to change: only for a Copy no other thread shares.
  mjModel* get_mutable() { return model_.get(); }
  const mjModel* operator->() const { return model_.get(); }
  int id(mjtObj type, const std::string& name) const;  // throws when absent

 private:
  // Owns `raw` and attaches `libraries` to it.
  static Model Adopt(mjModel* raw, std::vector<PluginLibrary> libraries, const std::string& source_name);

  std::shared_ptr<mjModel> model_;        // detaches the plugins, then frees
  std::vector<PluginLibrary> libraries_;  // attached to it (never unloaded: they outlive every model)
};

struct DataDeleter {
  void operator()(mjData* d) const { mj_deleteData(d); }
};
using Data = std::unique_ptr<mjData, DataDeleter>;
inline Data make_data(const Model& model) { return Data(mj_makeData(model.get())); }

}  // namespace softwrist::sim
