#pragma once
// The device an experiment simulates: the placement file's description, the MuJoCo model generated from it with
// the fPAM plugin loaded, and the hash of that model for the log's provenance.

#include <filesystem>
#include <string>

#include "io/json_reader.h"
#include "sim/device.h"
#include "sim/model.h"
#include "sim/model_builder.h"
#include "sim/plugins.h"

namespace softwrist::experiments {

struct SimulatedDevice {
  explicit SimulatedDevice(const std::filesystem::path& placement_file, const sim::ModelOptions& options = {});
  explicit SimulatedDevice(const sim::DeviceDescription& description, const sim::ModelOptions& options = {});

  // A config's pressure [kPa] as pascals, or an error naming `key` when it is outside this device's regulator range.
  double regulator_pressure(io::JsonReader& reader, const std::string& key, double pressure_kpa) const;

  sim::DeviceDescription description;
  std::string model_xml;
  sim::PluginSet plugins;  // declared before the model: the model detaches from them when freed
  sim::Model model;
  std::string model_hash;
};

}  // namespace softwrist::experiments
