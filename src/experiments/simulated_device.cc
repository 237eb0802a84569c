#include "experiments/simulated_device.h"

#include "experiments/trial_log.h"
#include "physics/units.h"

namespace softwrist::experiments {

SimulatedDevice::SimulatedDevice(const std::filesystem::path& placement_file, const sim::ModelOptions& options)
    : SimulatedDevice(sim::load_device(placement_file), options) {}

SimulatedDevice::SimulatedDevice(const sim::DeviceDescription& device, const sim::ModelOptions& options)
    : description(device),
      model_xml(sim::build_model_xml(device, options)),
      plugins(sim::PluginSet::Default()),
      model(sim::Model::FromXml(model_xml, plugins, "generated model")),
      model_hash(content_hash(model_xml)) {}

double SimulatedDevice::regulator_pressure(io::JsonReader& reader, const std::string& key, double pressure_kpa) const {
  const double max_kpa = units::pa_to_kpa(description.regulator.max_pressure);
  if (!(pressure_kpa >= 0.0 && pressure_kpa <= max_kpa)) {
    reader.fail(key, fmt::format("{} is outside the regulator's 0..{}", pressure_kpa, max_kpa));
  }
  return units::kpa_to_pa(pressure_kpa);
}

}  // namespace softwrist::experiments
