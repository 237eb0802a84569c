#pragma once
// A MuJoCo model loaded with its plugins attached, and its data, as RAII handles.

#include <filesystem>
#include <memory>
#include <string>

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

  const mjModel* get() const { return model_.get(); }
  const mjModel* operator->() const { return model_.get(); }
  int id(mjtObj type, const std::string& name) const;  // throws when absent

 private:
  std::shared_ptr<mjModel> model_;  // detaches the plugins, then frees
};

struct DataDeleter {
  void operator()(mjData* d) const { mj_deleteData(d); }
};
using Data = std::unique_ptr<mjData, DataDeleter>;
inline Data make_data(const Model& model) { return Data(mj_makeData(model.get())); }

}  // namespace softwrist::sim
