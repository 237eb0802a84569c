#include "sim/plugins.h"

#include <dlfcn.h>

#include <array>
#include <cstdlib>
#include <stdexcept>

#include <fmt/format.h>

namespace softwrist::sim {
namespace {

template <class Function>
Function symbol(void* handle, const char* name, const std::filesystem::path& file) {
  void* address = dlsym(handle, name);
  if (address == nullptr) throw std::runtime_error(fmt::format("plugin {}: missing symbol {}", file.string(), name));
  return reinterpret_cast<Function>(address);
}

}  // namespace

PluginLibrary PluginLibrary::Load(const std::filesystem::path& directory, const std::string& name) {
  const auto file = directory / ("lib" + name + ".so");
  if (!std::filesystem::exists(file)) {
    throw std::runtime_error(
        fmt::format("plugin '{}' not found: no {} (set SOFTWRIST_PLUGIN_DIR)", name, file.string()));
  }
  // Never closed: the library installs process-wide MuJoCo callbacks.
  void* handle = dlopen(file.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (handle == nullptr) throw std::runtime_error(fmt::format("plugin {}: {}", file.string(), dlerror()));
  if (symbol<int (*)()>(handle, "softwrist_plugin_abi_version", file)() != 1) {
    throw std::runtime_error(fmt::format("plugin {}: unsupported ABI version", file.string()));
  }
  PluginLibrary library;
  library.plugin_name_ = symbol<const char* (*)()>(handle, "softwrist_plugin_name", file)();
  library.attach_ = symbol<int (*)(const mjModel*, char*, int)>(handle, "softwrist_plugin_attach", file);
  library.detach_ = symbol<void (*)(const mjModel*)>(handle, "softwrist_plugin_detach", file);
  if (symbol<int (*)()>(handle, "softwrist_plugin_register", file)() != 0) {
    throw std::runtime_error(
        fmt::format("plugin {}: MuJoCo's user actuator callbacks belong to another library", file.string()));
  }
  return library;
}

int PluginLibrary::Attach(const mjModel* m) const {
  std::array<char, 1024> error{};
  const int count = attach_(m, error.data(), static_cast<int>(error.size()));
  if (count < 0) throw std::runtime_error(error.data());
  return count;
}

void PluginLibrary::Detach(const mjModel* m) const { detach_(m); }

std::filesystem::path default_plugin_dir() {
  if (const char* dir = std::getenv("SOFTWRIST_PLUGIN_DIR"); dir != nullptr && *dir != '\0') return dir;
  const std::filesystem::path build_dir = SOFTWRIST_BUILD_PLUGIN_DIR;
  if (std::filesystem::exists(build_dir)) return build_dir;
  return SOFTWRIST_INSTALL_PLUGIN_DIR;
}

PluginSet PluginSet::Load(const std::filesystem::path& directory, const std::vector<std::string>& names) {
  PluginSet set;
  for (const auto& name : names) set.libraries_.push_back(PluginLibrary::Load(directory, name));
  return set;
}

}  // namespace softwrist::sim
