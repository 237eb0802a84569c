#include "plugin_config.h"

#include <sstream>

namespace softwrist::plugin {

std::string config_text_name(std::string_view actuator_name) { return "plugin:" + std::string(actuator_name); }

std::optional<PluginConfig> PluginConfig::Parse(std::string_view text, std::string* error) {
  std::istringstream tokens{std::string(text)};
  PluginConfig config;
  if (!(tokens >> config.plugin_name_) || config.plugin_name_.find('=') != std::string::npos) {
    *error = "the configuration must start with the plugin's name";
    return std::nullopt;
  }
  std::string token;
  while (tokens >> token) {
    const auto equals = token.find('=');
    if (equals == std::string::npos || equals == 0 || equals + 1 == token.size()) {
      *error = "'" + token + "' is not key=value";
      return std::nullopt;
    }
    const std::string key = token.substr(0, equals);
    if (!config.attributes_.emplace(key, token.substr(equals + 1)).second) {
      *error = "attribute '" + key + "' given twice";
      return std::nullopt;
    }
  }
  return config;
}

std::optional<std::string> PluginConfig::Get(std::string_view key) const {
  const auto found = attributes_.find(key);
  if (found == attributes_.end()) return std::nullopt;
  return found->second;
}

std::vector<std::string> PluginConfig::Keys() const {
  std::vector<std::string> keys;
  for (const auto& [key, value] : attributes_) keys.push_back(key);
  return keys;
}

}  // namespace softwrist::plugin
