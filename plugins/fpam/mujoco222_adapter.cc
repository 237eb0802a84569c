// Wires the softwrist.fpam actuator plugin into MuJoCo 2.2.2, which predates MuJoCo's engine-plugin API (mjpPlugin,
// MuJoCo >= 2.3): an fPAM actuator is a <general dyntype="user" gaintype="user" biastype="user"> actuator whose
// configuration is the text <custom><text name="plugin:ACTUATOR" data="softwrist.fpam key=value ..."/>.
//  - mjcb_act_dyn: the regulator, act_dot = (clamp(ctrl) - act) / tau;
//  - mjcb_act_gain: 0 (the force is not linear in the activation);
//  - mjcb_act_bias: minus the fPAM's pull at the tendon's length and the regulated pressure (act); with routing=planar
//    (the actuator on the muscle's own joint) the muscle's torque at the joint's angle.
// A muscle with hysteresis has a companion actuator on its tendon or joint (FpamConfig::kHysteresisStatePlugin) whose
// act is the hysteresis branch: act_dyn gives Dahl's rate from the tendon's (or 2D path's) velocity; its force is 0. A
// muscle whose regulator is of second order has one (kPressureRatePlugin) whose act is the regulated pressure's rate.
// This is the only file that sees mjModel/mjData; moving to MuJoCo 3 replaces it with an mjpPlugin registration.
//
// Global state: MuJoCo 2.2.2's callbacks are process-wide function pointers, so this file keeps the one registry a
// plugin system needs, from each attached mjModel to its instances (MuJoCo 3 keeps the same in its plugin table
// and mjData::plugin_data). It is guarded by a shared mutex; instances are immutable and the per-step state (the
// activation) lives in mjData, so threads stepping different mjData of the same or different models are safe.

#include <atomic>
#include <cmath>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <shared_mutex>
#include <string>
#include <tuple>
#include <unordered_map>
#include <vector>

#include <mujoco/mujoco.h>

#include "fpam_actuator.h"
#include "mujoco_names.h"
#include "plugin_config.h"

#define SOFTWRIST_PLUGIN_EXPORT extern "C" __attribute__((visibility("default")))

namespace softwrist::plugin {
namespace {

// What each actuator of an attached model is to the plugin (indexed by actuator id): an fPAM (with the ids of its
// companions holding its hysteresis branch and its pressure's rate, if any), a companion of the fPAM `companion_of`,
// or nothing of ours.
enum class Companion { kNone, kHysteresisState, kPressureRate };
struct Instance {
  std::optional<FpamActuator> fpam;
  int hysteresis_actuator = -1;
  int rate_actuator = -1;
  Companion companion = Companion::kNone;
  int companion_of = -1;
};
using Instances = std::vector<Instance>;

std::shared_mutex& RegistryMutex() {
  static std::shared_mutex mutex;
  return mutex;
}
std::unordered_map<const mjModel*, std::shared_ptr<const Instances>>& Registry() {
  static std::unordered_map<const mjModel*, std::shared_ptr<const Instances>> registry;
  return registry;
}

// Bumped (under the unique lock) on every attach and detach, so that a thread's cached lookup is never used for a
// freed model whose address a new model happens to reuse.
std::atomic<std::uint64_t>& Generation() {
  static std::atomic<std::uint64_t> generation{1};
  return generation;
}

// Each thread remembers its last model's instances: MuJoCo calls the hooks for every actuator every step, and the
// cache saves the shared lock and the hash lookup there.
struct ThreadCache {
  const mjModel* model = nullptr;
  std::uint64_t generation = 0;
  std::shared_ptr<const Instances> instances;
};

const Instance* Find(const mjModel* m, int id) {
  // initial-exec: the cache is read twice per actuator per step, and a dlopen()ed library's default TLS model
  // costs a __tls_get_addr call on each read (`softwrist bench sim`). The cache and its guard (48 bytes) fit the
  // static TLS glibc keeps for dlopen()ed libraries (512 bytes); were it used up, dlopen would fail, not slow down.
  __attribute__((tls_model("initial-exec"))) thread_local ThreadCache cache;
  const std::uint64_t generation = Generation().load(std::memory_order_acquire);
  if (cache.model != m || cache.generation != generation) {
    std::shared_lock lock(RegistryMutex());
    const auto found = Registry().find(m);
    cache = {m, Generation().load(std::memory_order_relaxed), found == Registry().end() ? nullptr : found->second};
  }
  if (cache.instances == nullptr) return nullptr;
  return &(*cache.instances)[static_cast<std::size_t>(id)];
}

// mjModel::actuator_gear holds six numbers per actuator (MuJoCo 2.2.2 names no constant for it).
constexpr int kGearSize = 6;

// MuJoCo 2.2.2 keeps the activations of the stateful actuators, which come last, in d->act.
int ActivationIndex(const mjModel* m, int id) { return id - (m->nu - m->na); }

mjtNum ActDyn(const mjModel* m, const mjData* d, int id) {
  const Instance* instance = Find(m, id);
  if (instance == nullptr) return 0;
  const auto act = [&](int actuator) { return d->act[ActivationIndex(m, actuator)]; };
  const int muscle_id = instance->fpam ? id : instance->companion_of;
  if (muscle_id < 0) return 0;
  const Instance* muscle = instance->fpam ? instance : Find(m, muscle_id);
  const FpamActuator& fpam = *muscle->fpam;
  if (instance->companion == Companion::kHysteresisState) {
    // On a joint (routing=planar) the companion's velocity is the joint's rate: Dahl's rate wants the path's.
    const double velocity =
        fpam.planar() ? fpam.PathVelocity(d->actuator_length[id], d->actuator_velocity[id]) : d->actuator_velocity[id];
    return fpam.BranchRate(act(id), velocity);
  }
  if (muscle->rate_actuator < 0) return fpam.PressureRate(d->ctrl[id], act(id));
  const auto rates =
      fpam.SecondOrderStep(d->ctrl[muscle_id], act(muscle_id), act(muscle->rate_actuator), m->opt.timestep);
  return instance->fpam ? rates.pressure : rates.pressure_rate;
}

mjtNum ActGain(const mjModel*, const mjData*, int) { return 0; }

mjtNum ActBias(const mjModel* m, const mjData* d, int id) {
  const Instance* instance = Find(m, id);
  if (instance == nullptr || !instance->fpam) return 0;  // a companion pulls nothing
  const int state = instance->hysteresis_actuator;
  const double branch = state >= 0 ? d->act[ActivationIndex(m, state)] : 0.0;
  const double pressure_kpa = d->act[ActivationIndex(m, id)];
  // A tendon's force pulls (negative along it); a joint's (routing=planar, gear +1 in the muscle's own direction)
  // is the muscle's torque in that direction.
  if (instance->fpam->planar()) return instance->fpam->Torque(d->actuator_length[id], pressure_kpa, branch);
  return -instance->fpam->Force(d->actuator_length[id], pressure_kpa, branch);
}

// The companion of kind `kind` of the fPAM `id`: the actuator ACTUATOR + suffix configured as the companion's plugin,
// on the same tendon. Its id, or -1 with the problem and the actuator it concerns.
int FindCompanion(const mjModel* m, int id, Companion kind, std::string* problem, int* blame) {
  const bool state = kind == Companion::kHysteresisState;
  const std::string_view suffix = state ? FpamConfig::kHysteresisStateSuffix : FpamConfig::kPressureRateSuffix;
  const std::string_view plugin = state ? FpamConfig::kHysteresisStatePlugin : FpamConfig::kPressureRatePlugin;
  const std::string name = actuator_name(m, id) + std::string(suffix);
  const int companion = mj_name2id(m, mjOBJ_ACTUATOR, name.c_str());
  const int text = companion < 0 ? -1 : mj_name2id(m, mjOBJ_TEXT, config_text_name(name).c_str());
  std::string ignored;
  const auto config = text < 0 ? std::nullopt : PluginConfig::Parse(m->text_data + m->text_adr[text], &ignored);
  if (!config || config->plugin_name() != plugin) {
    *problem = std::string(state ? "has hysteresis" : "has a second-order regulator") + " but no actuator '" + name +
               "' configured as " + std::string(plugin) + " to hold its " + (state ? "state" : "pressure's rate");
    return -1;
  }
  if (m->actuator_trntype[companion] != m->actuator_trntype[id] ||
      m->actuator_trnid[2 * companion] != m->actuator_trnid[2 * id] ||
      m->actuator_gear[kGearSize * companion] != m->actuator_gear[kGearSize * id]) {
    *problem = "must act on the same tendon (or joint, with the same gear) as '" + actuator_name(m, id) + "'";
    *blame = companion;
    return -1;
  }
  return companion;
}

// What is wrong with an fPAM's transmission: routing=spatial reads a tendon's length; routing=planar a hinge's angle
// in the muscle's own direction, which a gear of +-1 gives (FpamConfig::PlanarPath).
std::optional<std::string> TransmissionProblem(const mjModel* m, int id, bool planar) {
  const int type = m->actuator_trntype[id];
  if (!planar) {
    if (type != mjTRN_TENDON) return "routing=spatial needs a tendon transmission (or set routing=planar)";
    return std::nullopt;
  }
  const int joint = m->actuator_trnid[2 * id];
  if (type != mjTRN_JOINT || m->jnt_type[joint] != mjJNT_HINGE)
    return "routing=planar needs a hinge joint transmission";
  if (std::abs(std::abs(m->actuator_gear[kGearSize * id]) - 1.0) > 1e-12)
    return "routing=planar needs gear +1 or -1 (the muscle's own direction)";
  return std::nullopt;
}

void CopyError(const std::string& message, char* error, int error_size) {
  if (error == nullptr || error_size <= 0) return;
  const std::size_t n = std::min(message.size(), static_cast<std::size_t>(error_size - 1));
  message.copy(error, n);
  error[n] = '\0';
}

}  // namespace
}  // namespace softwrist::plugin

using softwrist::plugin::FpamActuator;

SOFTWRIST_PLUGIN_EXPORT int softwrist_plugin_abi_version() { return 1; }

SOFTWRIST_PLUGIN_EXPORT const char* softwrist_plugin_name() { return FpamActuator::kPluginName.data(); }

// Installs the user-actuator callbacks. Idempotent. Returns 0, or -1 when another library already owns them.
SOFTWRIST_PLUGIN_EXPORT int softwrist_plugin_register() {
  using namespace softwrist::plugin;
  std::unique_lock lock(RegistryMutex());
  const bool ours = mjcb_act_dyn == ActDyn && mjcb_act_gain == ActGain && mjcb_act_bias == ActBias;
  const bool free = mjcb_act_dyn == nullptr && mjcb_act_gain == nullptr && mjcb_act_bias == nullptr;
  if (!ours && !free) return -1;
  mjcb_act_dyn = ActDyn;
  mjcb_act_gain = ActGain;
  mjcb_act_bias = ActBias;
  return 0;
}

// Creates the instances for every actuator of `m` configured for softwrist.fpam, and pairs each fPAM with hysteresis
// or a second-order regulator with its companions. Returns how many fPAMs, or -1 with the reason in `error` (naming the
// actuator and the attribute) when any configuration is invalid.
SOFTWRIST_PLUGIN_EXPORT int softwrist_plugin_attach(const mjModel* m, char* error, int error_size) {
  using namespace softwrist::plugin;
  auto instances = std::make_shared<Instances>(static_cast<std::size_t>(m->nu));
  int count = 0;
  std::string message;
  const auto fail = [&](int id, const std::string& problem) {
    CopyError("actuator '" + actuator_name(m, id) + "': " + problem, error, error_size);
    return -1;
  };
  for (int id = 0; id < m->nu; ++id) {
    const int text = mj_name2id(m, mjOBJ_TEXT, config_text_name(actuator_name(m, id)).c_str());
    if (text < 0) continue;
    const auto config = PluginConfig::Parse(m->text_data + m->text_adr[text], &message);
    if (!config) return fail(id, message);
    const bool fpam = config->plugin_name() == FpamActuator::kPluginName;
    const bool companion = config->plugin_name() == FpamConfig::kHysteresisStatePlugin ||
                           config->plugin_name() == FpamConfig::kPressureRatePlugin;
    if (!fpam && !companion) continue;
    // The force is not linear in the activation: a gain of 0, fixed (MuJoCo then calls no gain hook, which the
    // plugin's cost is measured with, `softwrist bench sim`) or from the user hook, which returns 0.
    const bool zero_gain = m->actuator_gaintype[id] == mjGAIN_USER ||
                           (m->actuator_gaintype[id] == mjGAIN_FIXED && m->actuator_gainprm[id * mjNGAIN] == 0.0);
    if (m->actuator_dyntype[id] != mjDYN_USER || m->actuator_biastype[id] != mjBIAS_USER || !zero_gain) {
      return fail(id, config->plugin_name() +
                          " needs dyntype and biastype 'user', and gaintype 'user' or 'fixed' with gainprm 0");
    }
    if (companion) continue;  // paired with its fPAM below
    auto actuator = FpamActuator::Create(*config, actuator_name(m, id), &message);
    if (!actuator) {
      CopyError(message, error, error_size);
      return -1;
    }
    if (const auto problem = TransmissionProblem(m, id, actuator->planar())) return fail(id, *problem);
    (*instances)[static_cast<std::size_t>(id)].fpam = std::move(actuator);
    ++count;
  }
  for (int id = 0; id < m->nu; ++id) {
    Instance& muscle = (*instances)[static_cast<std::size_t>(id)];
    if (!muscle.fpam) continue;
    const FpamConfig& config = muscle.fpam->config();
    for (const auto& [needed, kind, slot] :
         {std::tuple{config.hysteresis.active(), Companion::kHysteresisState, &muscle.hysteresis_actuator},
          std::tuple{config.regulator.second_order(), Companion::kPressureRate, &muscle.rate_actuator}}) {
      if (!needed) continue;
      // The rates make one explicit step exact (FpamActuator::SecondOrderStep); RK4 would take them as slopes.
      if (kind == Companion::kPressureRate && m->opt.integrator == mjINT_RK4)
        return fail(id, "a second-order regulator needs the Euler integrator, not RK4");
      int blame = id;
      const int companion = FindCompanion(m, id, kind, &message, &blame);
      if (companion < 0) return fail(blame, message);
      *slot = companion;
      (*instances)[static_cast<std::size_t>(companion)].companion = kind;
      (*instances)[static_cast<std::size_t>(companion)].companion_of = id;
    }
  }
  std::unique_lock lock(RegistryMutex());
  Registry()[m] = std::move(instances);
  Generation().fetch_add(1, std::memory_order_release);
  return count;
}

SOFTWRIST_PLUGIN_EXPORT void softwrist_plugin_detach(const mjModel* m) {
  using namespace softwrist::plugin;
  std::unique_lock lock(RegistryMutex());
  Registry().erase(m);
  Generation().fetch_add(1, std::memory_order_release);
}
