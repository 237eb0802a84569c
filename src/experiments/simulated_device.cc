#include "experiments/simulated_device.h"

#include "experiments/trial_log.h"
#include "sim/model_builder.h"

namespace softwrist::experiments {

SimulatedDevice::SimulatedDevice(const std::filesystem::path& placement_file)
    : SimulatedDevice(sim::load_device(placement_file)) {}

SimulatedDevice::SimulatedDevice(const sim::DeviceDescription& device)
    : description(device),
      model_xml(sim::build_model_xml(device)),
      plugins(sim::PluginSet::Default()),
      model(sim::Model::FromXml(model_xml, plugins, "generated model")),
      model_hash(content_hash(model_xml)) {}

}  // namespace softwrist::experiments
