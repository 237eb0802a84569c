#pragma once
// Loading plugins (shared libraries in a plugin directory) by name, and attaching them to a model: the part of
// MuJoCo 3's plugin loading (mj_loadPluginLibrary / mj_loadAllPluginLibraries) that MuJoCo 2.2.2 lacks.
//
// A plugin library exports (C linkage): softwrist_plugin_abi_version() == 1, softwrist_plugin_name(),
// softwrist_plugin_register(), softwrist_plugin_attach(const mjModel*, char* error, int size) and
// softwrist_plugin_detach(const mjModel*). See plugins/fpam/mujoco222_adapter.cc.

#include <filesystem>
#include <string>
#include <vector>

#include <mujoco/mujoco.h>

namespace softwrist::sim {

class PluginLibrary {
 public:
  // Loads lib<name>.so from `directory` and registers it. Throws std::runtime_error naming the file and the reason.
  static PluginLibrary Load(const std::filesystem::path& directory, const std::string& name);

  const std::string& plugin_name() const { return plugin_name_; }
  // Number of actuators claimed; throws std::runtime_error with the plugin's reason on an invalid configuration.
  int Attach(const mjModel* m) const;
  void Detach(const mjModel* m) const;

 private:
  std::string plugin_name_;
  int (*attach_)(const mjModel*, char*, int) = nullptr;
  void (*detach_)(const mjModel*) = nullptr;
};

// $SOFTWRIST_PLUGIN_DIR if set, else the build tree's plugins/ when it exists, else <prefix>/lib/softwrist/plugins.
std::filesystem::path default_plugin_dir();

// The plugins a model may use; by default the fPAM actuator from default_plugin_dir().
class PluginSet {
 public:
  static PluginSet Load(const std::filesystem::path& directory,
                        const std::vector<std::string>& names = {"softwrist_fpam"});
  static PluginSet Default() { return Load(default_plugin_dir()); }
  const std::vector<PluginLibrary>& libraries() const { return libraries_; }

 private:
  std::vector<PluginLibrary> libraries_;
};

}  // namespace softwrist::sim
