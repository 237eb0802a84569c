#include "sim/model.h"

#include <array>
#include <cstring>
#include <stdexcept>

#include <fmt/format.h>

#include "io/text_file.h"
#include "mujoco_names.h"
#include "plugin_config.h"

namespace softwrist::sim {
namespace {

using plugin::actuator_name;

// Every actuator left to user callbacks must name a plugin that is loaded.
void check_plugin_names(const mjModel* m, const PluginSet& plugins, const std::string& source) {
  for (int id = 0; id < m->nu; ++id) {
    const bool user = m->actuator_dyntype[id] == mjDYN_USER || m->actuator_gaintype[id] == mjGAIN_USER ||
                      m->actuator_biastype[id] == mjBIAS_USER;
    const int text = mj_name2id(m, mjOBJ_TEXT, plugin::config_text_name(actuator_name(m, id)).c_str());
    if (text < 0) {
      if (user) {
        throw std::runtime_error(
            fmt::format("{}: actuator '{}' has user dynamics/gain/bias but no <custom><text "
                        "name=\"{}\"> naming its plugin",
                        source, actuator_name(m, id), plugin::config_text_name(actuator_name(m, id))));
      }
      continue;
    }
    std::string error;
    const auto config = plugin::PluginConfig::Parse(m->text_data + m->text_adr[text], &error);
    if (!config) throw std::runtime_error(fmt::format("{}: actuator '{}': {}", source, actuator_name(m, id), error));
    bool known = false;
    // A plugin's own configurations: its name, or its name and a part ("softwrist.fpam.hysteresis_state").
    const std::string& name = config->plugin_name();
    for (const auto& library : plugins.libraries()) {
      const std::string& own = library.plugin_name();
      known = known || name == own || (name.size() > own.size() && name.starts_with(own) && name[own.size()] == '.');
    }
    if (!known) {
      throw std::runtime_error(
          fmt::format("{}: actuator '{}': unknown plugin '{}'", source, actuator_name(m, id), config->plugin_name()));
    }
  }
}

}  // namespace

Model Model::FromXml(const std::string& xml, const PluginSet& plugins, const std::string& source_name) {
  mjVFS vfs;
  mj_defaultVFS(&vfs);
  const std::string file = "model.xml";
  if (mj_makeEmptyFileVFS(&vfs, file.c_str(), static_cast<int>(xml.size())) != 0) {
    mj_deleteVFS(&vfs);
    throw std::runtime_error(fmt::format("{}: cannot allocate the model text", source_name));
  }
  std::memcpy(vfs.filedata[vfs.nfile - 1], xml.data(), xml.size());
  std::array<char, 1024> error{};
  mjModel* raw = mj_loadXML(file.c_str(), &vfs, error.data(), static_cast<int>(error.size()));
  mj_deleteVFS(&vfs);
  if (raw == nullptr) throw std::runtime_error(fmt::format("{}: {}", source_name, error.data()));

  try {
    check_plugin_names(raw, plugins, source_name);
  } catch (...) {
    mj_deleteModel(raw);
    throw;
  }
  return Adopt(raw, plugins.libraries(), source_name);
}

Model Model::Adopt(mjModel* raw, std::vector<PluginLibrary> libraries, const std::string& source_name) {
  Model model;
  model.libraries_ = libraries;
  // The deleter detaches before freeing.
  model.model_ = std::shared_ptr<mjModel>(raw, [libraries = std::move(libraries)](mjModel* m) {
    for (const auto& library : libraries) library.Detach(m);
    mj_deleteModel(m);
  });
  for (const auto& library : model.libraries_) {
    try {
      library.Attach(raw);
    } catch (const std::runtime_error& e) {
      throw std::runtime_error(fmt::format("{}: {}", source_name, e.what()));
    }
  }
  return model;
}

Model Model::Copy() const {
  mjModel* raw = mj_copyModel(nullptr, model_.get());
  if (raw == nullptr) throw std::runtime_error("cannot copy the model (out of memory)");
  return Adopt(raw, libraries_, "a copy of the model");
}

Model Model::FromFile(const std::filesystem::path& path, const PluginSet& plugins) {
  return FromXml(io::read_text_file(path), plugins, path.string());
}

int Model::id(mjtObj type, const std::string& name) const {
  const int id = mj_name2id(model_.get(), type, name.c_str());
  if (id < 0) throw std::runtime_error(fmt::format("model has no object named '{}'", name));
  return id;
}

}  // namespace softwrist::sim
