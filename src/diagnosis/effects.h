#pragma once
// The catalogue of candidate unmodelled effects: each a switchable, parameterised extension of the nominal model.
// Most live in the model itself (the placement file the MuJoCo model and the plugin are generated from: mount
// stiffness, fPAM r0 and eps_max, regulator time constant, wrist radius, relaxed-wrist stiffness and damping); the
// rest act where the model meets the measurement (regulator dead time on the commands, IMU offset and latency on the
// angles, loading/unloading hysteresis of the fPAM force on the tensile rig).

#include <array>
#include <filesystem>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "diagnosis/real_data.h"
#include "sim/device.h"

namespace softwrist::diagnosis {

enum class EffectId { kMountStretch, kFpamParams, kRegulatorLag, kHysteresis, kWrapGeometry, kPassiveWrist, kImuBias };

struct ParameterSpec {
  std::string name;  // with its unit: K1_n_per_cm2, dead_time_s, ...
  double lower = 0.0, upper = 0.0;
  bool log_scale = false;  // searched in log space (stiffnesses spanning decades)
  double neutral = 0.0;    // the value that leaves the nominal model unchanged, where one exists
  // Beyond the effect's base form (a regulator's second order): fitted only after the base form, and kept only where
  // it lowers the held-out error by more than one standard error (effect_fit.h).
  bool extension = false;
  // Acts on trials none of the effect's other parameters acts on (a regulator's carry-over between range-of-motion
  // conditions): separable from them, so the start grid crosses its levels with theirs instead of joining them.
  bool separable = false;

  // The value <-> the unit interval the fits search in (log space where log_scale); from_unit clamps into [0, 1].
  double to_unit(double value) const;
  double from_unit(double u) const;
};

struct EffectSpec {
  EffectId id;
  std::string name;
  std::string description;
  std::vector<ParameterSpec> parameters;
  std::vector<TrialKind> acts_on;  // the kinds of data it changes
  // It changes a trajectory's angles only through the regulators' pressures (so not where measured pressures drive
  // the replay, replay.h PressureSource).
  bool through_regulators_only = false;
  bool acts_on_kind(TrialKind kind) const;
};

const std::vector<EffectSpec>& effect_catalogue();
const EffectSpec& effect_spec(EffectId id);
std::optional<EffectId> effect_from_name(std::string_view name);

// The model a replay runs: the nominal device with effects switched on.
struct ModelVariant {
  sim::DeviceDescription device;  // effects that live in the placement file are applied here
  // The rigs that trials name by their placement file (Conventions::placement), each with the same effects applied
  // as `device`: a muscle's, a mount's or a regulator's property is fitted once across all rigs.
  std::map<std::filesystem::path, sim::DeviceDescription> rigs;
  double regulator_dead_time = 0.0;  // [s] commands reach the regulators this late
  // The share of the previous range-of-motion condition's pressure its muscle still held when the next condition's
  // angles were zeroed (a regulator that vents slowly): ReplayEngine::predict_rom.
  double rom_residual_fraction = 0.0;
  double imu_offset_fe = 0.0, imu_offset_ur = 0.0;  // [rad] added to the measured angles
  double imu_latency = 0.0;                         // [s] the measured angles are this old
  double imu_axis_roll = 0.0;  // [rad] the angles' axes turned about the forearm: fe' = c fe - s ur, ur' = s fe + c ur
  // Each regulator's pressure monitor reads gain x pressure + offset (the tolerance fit's calibration; exact here).
  std::array<double, 4> monitor_gain{1.0, 1.0, 1.0, 1.0};
  std::array<double, 4> monitor_offset{};  // [Pa]

  // The device of the trial's rig: its placement file's, or `device` when it names none.
  const sim::DeviceDescription& device_for(const Trial& trial) const;
  // The device and every rig routed alike (sim::Routing; the diagnosis's choice, DiagnosisOptions::routing).
  void route(sim::Routing routing);
  bool routed_as(sim::Routing routing) const;
};

// Switches effect `id` on in `variant` with `values` in its spec's units (one per parameter). Values outside a
// physical device (a wrist radius reaching a mount) throw physics::InvalidParameter.
void apply_effect(EffectId id, std::span<const double> values, ModelVariant& variant);

// Where a fit of effect `id` starts: its neutral values, or the nominal device's own (regulator time constant, series
// mount stiffness and the mounts' law, the hysteresis); the middle of the range (in log space where searched so) when
// the nominal has no such value.
std::vector<double> fit_start(EffectId id, const sim::DeviceDescription& nominal);

// The fitted values with their names, and the values they imply (K1 and K2 of a series stiffness).
std::vector<std::pair<std::string, double>> describe_values(EffectId id, std::span<const double> values,
                                                            const sim::DeviceDescription& nominal);

}  // namespace softwrist::diagnosis
