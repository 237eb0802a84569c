// Wires the softwrist.fpam actuator plugin into MuJoCo 2.2.2, which predates MuJoCo's engine-plugin API (mjpPlugin,
// MuJoCo >= 2.3): an fPAM actuator is a <general dyntype="user" gaintype="user" biastype="user"> actuator whose
// configuration is the text <custom><text name="plugin:ACTUATOR" data="softwrist.fpam key=value ..."/>.
//  - mjcb_act_dyn: the regulator, act_dot = (clamp(ctrl) - act) / tau;
//  - mjcb_act_gain: 0 (the force is not linear in the activation);
//  - mjcb_act_bias: minus the fPAM's pull at the tendon's length and the regulated pressure (act).
// This is the only file that sees mjModel/mjData; moving to MuJoCo 3 replaces it with an mjpPlugin registration.
//
// Global state: MuJoCo 2.2.2's callbacks are process-wide function pointers, so this file keeps the one registry a
// plugin system needs, from each attached mjModel to its instances (MuJoCo 3 keeps the same in its plugin table
// and mjData::plugin_data). It is guarded by a shared mutex; instances are immutable and the per-step state (the
// activation) lives in mjData, so threads stepping different mjData of the same or different models are safe.

#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <shared_mutex>
#include <string>
#include <unordered_map>
#include <vector>

#include <mujoco/mujoco.h>

#include "fpam_actuator.h"
#include "mujoco_names.h"
#include "plugin_config.h"

#define SOFTWRIST_PLUGIN_EXPORT extern "C" __attribute__((visibility("default")))

namespace softwrist::plugin {
namespace {

using Instances = std::vector<std::optional<FpamActuator>>;  // indexed by actuator id

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

const FpamActuator* Find(const mjModel* m, int id) {
  thread_local ThreadCache cache;
  const std::uint64_t generation = Generation().load(std::memory_order_acquire);
  if (cache.model != m || cache.generation != generation) {
    std::shared_lock lock(RegistryMutex());
    const auto found = Registry().find(m);
    cache = {m, Generation().load(std::memory_order_relaxed), found == Registry().end() ? nullptr : found->second};
  }
  if (cache.instances == nullptr) return nullptr;
  const auto& instance = (*cache.instances)[static_cast<std::size_t>(id)];
  return instance ? &*instance : nullptr;
}

// MuJoCo 2.2.2 keeps the activations of the stateful actuators, which come last, in d->act.
int ActivationIndex(const mjModel* m, int id) { return id - (m->nu - m->na); }

mjtNum ActDyn(const mjModel* m, const mjData* d, int id) {
  const FpamActuator* fpam = Find(m, id);
  if (fpam == nullptr) return 0;
  return fpam->PressureRate(d->ctrl[id], d->act[ActivationIndex(m, id)]);
}

mjtNum ActGain(const mjModel*, const mjData*, int) { return 0; }

mjtNum ActBias(const mjModel* m, const mjData* d, int id) {
  const FpamActuator* fpam = Find(m, id);
  if (fpam == nullptr) return 0;
  return -fpam->Force(d->actuator_length[id], d->act[ActivationIndex(m, id)]);
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

// Creates the instances for every actuator of `m` configured for softwrist.fpam. Returns how many, or -1 with the
// reason in `error` (naming the actuator and the attribute) when any configuration is invalid.
SOFTWRIST_PLUGIN_EXPORT int softwrist_plugin_attach(const mjModel* m, char* error, int error_size) {
  using namespace softwrist::plugin;
  auto instances = std::make_shared<Instances>(static_cast<std::size_t>(m->nu));
  int count = 0;
  for (int id = 0; id < m->nu; ++id) {
    const int text = mj_name2id(m, mjOBJ_TEXT, config_text_name(actuator_name(m, id)).c_str());
    if (text < 0) continue;
    std::string message;
    const auto config = PluginConfig::Parse(m->text_data + m->text_adr[text], &message);
    if (!config) {
      CopyError("actuator '" + actuator_name(m, id) + "': " + message, error, error_size);
      return -1;
    }
    if (config->plugin_name() != FpamActuator::kPluginName) continue;
    if (m->actuator_dyntype[id] != mjDYN_USER || m->actuator_gaintype[id] != mjGAIN_USER ||
        m->actuator_biastype[id] != mjBIAS_USER) {
      CopyError("actuator '" + actuator_name(m, id) + "': softwrist.fpam needs dyntype, gaintype and biastype 'user'",
                error, error_size);
      return -1;
    }
    auto actuator = FpamActuator::Create(*config, actuator_name(m, id), &message);
    if (!actuator) {
      CopyError(message, error, error_size);
      return -1;
    }
    (*instances)[static_cast<std::size_t>(id)] = std::move(actuator);
    ++count;
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
