#pragma once
// The simulated real device: the tensile specimen, the torque rig's flexor, the prototype's four muscles, four
// pressure channels, the hand and wrist, the IMUs. Nominal values come from the paper's tables; where the paper
// gives none, the source is cited beside the value (device.cc).

#include <array>

#include <nlohmann/json.hpp>

#include "independent_device/muscle.h"
#include "independent_device/random.h"
#include "independent_device/regulator.h"
#include "independent_device/sensors.h"
#include "independent_device/wrist_dynamics.h"

namespace softwrist::independent {

enum MuscleIndex : std::size_t { kFlexor = 0, kExtensor = 1, kUlnar = 2, kRadial = 3 };
inline constexpr std::array<const char*, 4> kMuscleNames{"flexor", "extensor", "ulnar", "radial"};

struct DeviceSpec {
  MuscleSpec tensile_specimen;          // the flexor fPAM in the tensile tester (L0 = 34 cm, no mounts)
  MuscleSpec rig_flexor;                // the same fPAM on the torque rig (Table torque_measurement_parameters)
  std::array<MuscleSpec, 4> prototype;  // Table RoM
  std::array<RegulatorSpec, 4> regulators;
  HandSegment hand;
  PassiveWrist passive;
  ImuSpec imu;
  double rig_angle_offset_rad = 0.0;  // the hand on the rig's plate is never exactly at the plate's angle
};

DeviceSpec nominal_device();
// Device-to-device variation of a few per cent (returns what was drawn, for truth.json).
nlohmann::json apply_variation(DeviceSpec& device, Rng& rng);

}  // namespace softwrist::independent
