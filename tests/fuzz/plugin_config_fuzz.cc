// Fuzz target: the softwrist.fpam plugin's configuration as read from a loaded model. The input is the text of an
// actuator's <custom><text name="plugin:fpam" data="..."/> in a one-muscle model; the model is loaded with MuJoCo
// and the plugin attached as sim::Model attaches it (plugins/fpam/mujoco222_adapter.cc is linked in). A
// configuration is either refused with a message naming the actuator (and the attribute), or attached; an attached
// one gives finite forces when stepped at its full pressure.

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>

#include <mujoco/mujoco.h>

#include "fuzz_check.h"

extern "C" int softwrist_plugin_register();
extern "C" int softwrist_plugin_attach(const mjModel* m, char* error, int error_size);
extern "C" void softwrist_plugin_detach(const mjModel* m);

namespace {

std::string xml_escaped(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

// One muscle over one hinge, routed as the generated models route theirs (model_builder.cc), much smaller.
std::string one_muscle_model(const std::string& config) {
  return R"(<mujoco model="fuzz">
  <option timestep="0.001"/>
  <custom><text name="plugin:fpam" data=")" + xml_escaped(config) + R"("/></custom>
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
  const std::string config(reinterpret_cast<const char*>(data), size);
  if (config.find('\0') != std::string::npos) return 0;  // not representable in an XML attribute
  static const bool registered = softwrist_plugin_register() == 0;
  FUZZ_CHECK(registered);
  mjModel* m = load(one_muscle_model(config));
  if (m == nullptr) return 0;  // characters XML does not allow in an attribute: MuJoCo's parser says so
  std::array<char, 512> error{};
  const int attached = softwrist_plugin_attach(m, error.data(), static_cast<int>(error.size()));
  if (attached < 0) {
    softwrist::fuzz::check_names_source(error.data(), "actuator 'fpam'");
  } else if (attached == 1) {
    mjData* d = mj_makeData(m);
    d->ctrl[0] = 137.0;
    for (int step = 0; step < 20; ++step) mj_step(m, d);
    FUZZ_CHECK(std::isfinite(d->actuator_force[0]) && std::isfinite(d->qpos[0]) && std::isfinite(d->act[0]),
               "force %g, angle %g, pressure %g", d->actuator_force[0], d->qpos[0], d->act[0]);
    mj_deleteData(d);
  }
  softwrist_plugin_detach(m);
  mj_deleteModel(m);
  return 0;
}
