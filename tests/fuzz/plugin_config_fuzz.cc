// Fuzz target: the softwrist.fpam plugin's configuration as read from a loaded model. The input is the text of an
// actuator's <custom><text name="plugin:fpam" data="..."/> in a one-muscle model loaded with MuJoCo, and the plugin
// is attached as sim::Model attaches it (plugins/fpam/mujoco222_adapter.cc is linked in). A
// configuration is either refused with a message naming the actuator (and the attribute), or attached; an attached
// one gives finite forces when stepped at its full pressure.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>

#include <mujoco/mujoco.h>

#include "fpam_actuator.h"
#include "fuzz_check.h"
#include "plugin_config.h"

extern "C" int softwrist_plugin_register();
extern "C" int softwrist_plugin_attach(const mjModel* m, char* error, int error_size);
extern "C" void softwrist_plugin_detach(const mjModel* m);

namespace {

constexpr std::size_t kMaxConfig = 4096;

// One muscle over one hinge, routed as the generated models route theirs (model_builder.cc), much smaller. `config`
// holds no XML markup.
std::string one_muscle_model(const std::string& config) {
  return R"(<mujoco model="fuzz">
  <option timestep="0.001"/>
  <custom><text name="plugin:fpam" data=")" +
         config + R"("/></custom>
  <worldbody>
    <site name="forearm_mount" pos="-0.2 0 0.02"/>
    <body name="hand">
      <joint name="wrist" type="hinge" axis="0 1 0" range="-1.4 1.4" limited="true" damping="0.03"/>
      <geom type="capsule" fromto="0 0 0 0.19 0 0" size="0.03" mass="0.45"/>
      <site name="hand_mount" pos="0.08 0 0.02"/>
    </body>
  </worldbody>
  <tendon><spatial name="fpam"><site site="forearm_mount"/><site site="hand_mount"/></spatial></tendon>
  <actuator>
    <general name="fpam" tendon="fpam" dyntype="user" gaintype="user" biastype="user" ctrllimited="true"
             ctrlrange="0 137" actlimited="true" actrange="0 137"/>
  </actuator>
</mujoco>)";
}

mjModel* load(const std::string& xml) {
  mjVFS vfs;
  mj_defaultVFS(&vfs);
  mj_makeEmptyFileVFS(&vfs, "fuzz.xml", static_cast<int>(xml.size()));
  std::memcpy(vfs.filedata[vfs.nfile - 1], xml.data(), xml.size());
  std::array<char, 1024> error{};
  mjModel* m = mj_loadXML("fuzz.xml", &vfs, error.data(), static_cast<int>(error.size()));
  mj_deleteVFS(&vfs);
  return m;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // The model is loaded once, with room for 4 KiB of configuration; each input is written into the loaded model's
  // text buffer, where the plugin reads it (MuJoCo's XML parser is MuJoCo's to fuzz, and at ~4 ms a load it would
  // keep this target at ~250 inputs/s).
  static const bool registered = softwrist_plugin_register() == 0;
  FUZZ_CHECK(registered);
  // MuJoCo's warnings (an unstable simulation, which it detects and resets) would go to MUJOCO_LOG.TXT: the state
  // is checked below instead.
  mju_user_warning = [](const char*) {};
  static mjModel* const m = load(one_muscle_model(std::string(kMaxConfig, 'x')));
  FUZZ_CHECK(m != nullptr && m->ntext == 1 && m->text_size[0] == static_cast<int>(kMaxConfig) + 1);
  char* text = m->text_data + m->text_adr[0];
  const std::size_t length = std::min(size, kMaxConfig);
  std::memcpy(text, data, length);
  text[length] = '\0';  // a NUL inside the input ends the text early, as it would in MuJoCo's buffer

  std::array<char, 512> error{};
  const int attached = softwrist_plugin_attach(m, error.data(), static_cast<int>(error.size()));
  if (attached < 0) {
    softwrist::fuzz::check_names_source(error.data(), "actuator 'fpam'");
    return 0;
  }
  if (attached == 1) {
    // The force law MuJoCo calls: finite and non-negative at any tendon length and pressure (inputs outside are
    // clamped); the pressure rate finite.
    std::string message;
    const auto parsed = softwrist::plugin::PluginConfig::Parse(text, &message);
    FUZZ_CHECK(parsed.has_value());
    const auto fpam = softwrist::plugin::FpamActuator::Create(*parsed, "fpam", &message);
    FUZZ_CHECK(fpam.has_value(), "attached, yet Create refuses it: %s", message.c_str());
    for (double tendon_length : {0.0, 1e-3, 0.05, 0.2, 0.3, 0.5, 2.0, 20.0}) {
      for (double kpa : {0.0, 10.0, 68.0, 137.0, 1000.0}) {
        const double force = fpam->Force(tendon_length, kpa);
        FUZZ_CHECK(std::isfinite(force) && force >= 0.0, "force %g at %g m, %g kPa", force, tendon_length, kpa);
        FUZZ_CHECK(std::isfinite(fpam->PressureRate(kpa, 0.5 * kpa)));
      }
    }
    mjData* d = mj_makeData(m);
    d->ctrl[0] = 137.0;
    for (int step = 0; step < 10; ++step) mj_step(m, d);
    // Finite, or, for parameters too stiff for the 1 ms step, detected by MuJoCo (which sim::WristSim turns into
    // an error); never a NaN force passed on unnoticed.
    const bool unstable = d->warning[mjWARN_BADQACC].number > 0 || d->warning[mjWARN_BADQVEL].number > 0 ||
                          d->warning[mjWARN_BADQPOS].number > 0;
    FUZZ_CHECK(
        unstable || (std::isfinite(d->actuator_force[0]) && std::isfinite(d->qpos[0]) && std::isfinite(d->act[0])),
        "force %g, angle %g, pressure %g", d->actuator_force[0], d->qpos[0], d->act[0]);
    mj_deleteData(d);
  }
  softwrist_plugin_detach(m);
  return 0;
}
