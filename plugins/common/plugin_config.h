#pragma once
// The configuration of one plugin instance: a plugin name and key=value attributes, the shape of MuJoCo 3's
// <plugin><instance><config key value/></instance></plugin>. In MuJoCo 2.2.2 it is stored per actuator as
//   <custom><text name="plugin:ACTUATOR" data="PLUGIN_NAME key=value key=value ..."/></custom>
// (list values are comma-separated, no spaces). Shared by the plugins and the sim layer that loads them.

#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace softwrist::plugin {

// The <custom><text> name that holds an actuator's plugin configuration.
std::string config_text_name(std::string_view actuator_name);

class PluginConfig {
 public:
  // Parses "PLUGIN_NAME key=value ...". Returns nullopt and sets *error on a malformed text.
  static std::optional<PluginConfig> Parse(std::string_view text, std::string* error);

  const std::string& plugin_name() const { return plugin_name_; }
  std::optional<std::string> Get(std::string_view key) const;
  std::vector<std::string> Keys() const;

 private:
  std::string plugin_name_;
  std::map<std::string, std::string, std::less<>> attributes_;
};

}  // namespace softwrist::plugin
