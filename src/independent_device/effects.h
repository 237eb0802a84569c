#pragma once
// The catalogue of effect forms: each belongs to a label (the class a diagnosis should name) and changes the
// device in a physically specific way, scaled by a level in (0, 1] (1: well above detection; the deviation from
// nominal grows linearly with the level).

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "independent_device/dataset.h"
#include "independent_device/device.h"

namespace softwrist::independent {

struct EffectDefinition {
  FormInfo info;
  // Changes the device; writes the physical parameter values at this level into `parameters`.
  void (*apply)(DeviceSpec& device, double level, nlohmann::json& parameters);
};

const std::vector<EffectDefinition>& effect_definitions();
// nullptr when unknown.
const EffectDefinition* find_effect(const std::string& form);
// Throws std::invalid_argument naming an unknown form, a repeated form or a level outside (0, 1].
void validate_effects(const std::vector<EffectSpec>& effects);

}  // namespace softwrist::independent
