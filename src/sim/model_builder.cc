#include "sim/model_builder.h"

#include <array>
#include <cmath>
#include <tuple>

#include <fmt/format.h>

#include "fpam_config.h"
#include "physics/torque_geometry.h"
#include "physics/units.h"
#include "plugin_config.h"
#include "sim/anatomy_visuals.h"

namespace softwrist::sim {
namespace {

// Each muscle's wrap cylinder: the quaternion that turns the cylinder's local z onto its joint axis.
constexpr std::array<const char*, 4> kCylinderQuats = {
    "0.70710678 -0.70710678 0 0",  // flexor: wraps about y
    "0.70710678 -0.70710678 0 0",  // extensor
    "1 0 0 0",                     // ulnar: wraps about z
    "1 0 0 0",                     // radial
};

// The mounts' markers: amber, neither red nor blue (those mean pressure, report/scene_style.h).
constexpr const char* kMountRgba = "0.96 0.68 0.12 1";

std::string vec(double x, const std::array<double, 3>& side, double offset) {
  return fmt::format("{:.6g} {:.6g} {:.6g}", x + 0.0, side[1] * offset + 0.0, side[2] * offset + 0.0);
}

// The plugin configuration of one muscle (plugins/fpam/fpam_config.h).
std::string plugin_config(const DeviceDescription& device, const MuscleMount& mount) {
  plugin::FpamConfig config{.law = device.muscle_law(mount),
                            .max_pressure_kpa = units::pa_to_kpa(device.regulator.max_pressure),
                            .regulator = device.regulator.response(),
                            .hysteresis = device.hysteresis};
  if (device.routing == Routing::kPlanar) config.planar = {mount.placement, mount.wrist_radius, mount.wrap_surface};
  return config.ToText();
}

// What an fPAM actuator (and its companions) acts on: its tendon (spatial), or its own joint in its own direction
// (planar; the tendon is then drawn only).
std::string transmission(const DeviceDescription& device, std::size_t muscle) {
  if (device.routing == Routing::kSpatial) return fmt::format("tendon=\"{}\"", kMuscleNames[muscle]);
  const auto index = static_cast<MuscleIndex>(muscle);
  return fmt::format("joint=\"{}\" gear=\"{:g}\"",
                     physics::axis_of(index) == physics::WristAxis::kFlexionExtension ? "wrist_fe" : "wrist_ur",
                     physics::direction_of(index));
}

// The MJCF of the four muscles: their plugin configurations, mounts and wrap cylinders, tendons and actuators (the
// four fPAMs first, so that ctrl[0..3] are the muscles' commands; then, where the fabric has hysteresis, each
// muscle's hysteresis state, and where the regulator is of second order, each muscle's pressure rate,
// plugins/fpam/fpam_config.h).
struct MuscleItems {
  std::string custom, forearm_items, hand_items, tendons, actuators;
};

MuscleItems muscle_items(const DeviceDescription& device, const ModelOptions& options) {
  const double max_kpa = units::pa_to_kpa(device.regulator.max_pressure);
  MuscleItems items;
  auto& [custom, forearm_items, hand_items, tendons, actuators] = items;
  for (std::size_t i = 0; i < kMuscleNames.size(); ++i) {
    const std::string name = kMuscleNames[i];
    const MuscleMount& m = device.muscles[i];
    const std::array<double, 3>& side = kMuscleSides[i];
    // The wrap cylinder about the wrist circle's centre C (the joint's unless moved, torque_geometry.h), fixed to the
    // forearm as the 2D law has it; its side site 2 r_w from C on the muscle's side. A surface that is not a circle:
    // its equivalent circle at the neutral wrist, which WristSim moves as the wrist turns.
    double r_w = m.wrist_radius, cx = m.wrap_surface.x, cy = m.wrap_surface.y;
    if (!m.wrap_surface.circular()) {
      const physics::Placement& p = m.placement;
      const physics::MusclePath path = physics::muscle_path(p, m.wrist_radius, 0.0, m.wrap_surface);
      const physics::EquivalentCircle circle = physics::equivalent_circle(p, m.wrist_radius, m.wrap_surface, 0.0, path);
      std::tie(cx, cy, r_w) = std::tuple{circle.x, circle.y, circle.radius};
      custom += fmt::format(
          "    <numeric name=\"{}{}\" size=\"8\" data=\"{:.10g} {:.10g} {:.10g} {:.10g} {:.10g} "
          "{:.10g} {:.10g} {:.10g}\"/>\n",
          kWrapSurfaceNumeric, name, p.d1, p.w1, p.d2, p.w2, m.wrist_radius, m.wrap_surface.x, m.wrap_surface.y,
          m.wrap_surface.aspect);
    }
    const bool moved = !(cx == 0.0 && cy == 0.0);
    const std::string cylinder_pos = moved ? fmt::format(" pos=\"{}\"", vec(cx, side, cy)) : "";
    forearm_items += fmt::format(
        "      <site name=\"{0}_forearm\" pos=\"{1}\" size=\"0.008\" rgba=\"{5}\"/>\n"
        "      <geom name=\"{0}_wrap\" type=\"cylinder\"{6} size=\"{2:.6g} 0.02\" quat=\"{3}\" contype=\"0\" "
        "conaffinity=\"0\" group=\"3\" rgba=\"0.8 0.8 0.8 0.3\" mass=\"0\"/>\n"
        "      <site name=\"{0}_side\" pos=\"{4}\" size=\"0.002\" group=\"3\"/>\n",
        name, vec(-m.placement.d1, side, m.placement.w1), r_w, kCylinderQuats[i], vec(cx, side, cy + 2.0 * r_w),
        kMountRgba, cylinder_pos);
    hand_items += fmt::format("        <site name=\"{0}_hand\" pos=\"{1}\" size=\"0.008\" rgba=\"{2}\"/>\n", name,
                              vec(m.placement.d2, side, m.placement.w2), kMountRgba);
    tendons += fmt::format(
        "    <spatial name=\"{0}\" width=\"0.006\" rgba=\"0.2 0.45 0.95 1\">\n"
        "      <site site=\"{0}_forearm\"/>\n      <geom geom=\"{0}_wrap\" sidesite=\"{0}_side\"/>\n"
        "      <site site=\"{0}_hand\"/>\n    </spatial>\n",
        name);
    if (options.actuators == ActuatorKind::kFpamPlugin) {
      custom += fmt::format("    <text name=\"{}\" data=\"{}\"/>\n", plugin::config_text_name(name),
                            plugin_config(device, m));
      actuators += fmt::format(
          "    <general name=\"{0}\" {2} dyntype=\"user\" gaintype=\"fixed\" gainprm=\"0\" "
          "biastype=\"user\" ctrllimited=\"true\" ctrlrange=\"0 {1:.10g}\" actlimited=\"true\" actrange=\"0 "
          "{1:.10g}\"/>\n",
          name, max_kpa, transmission(device, i));
    } else {
      actuators += fmt::format("    <general name=\"{0}\" tendon=\"{0}\" gainprm=\"1\"/>\n", name);
    }
  }
  if (options.actuators != ActuatorKind::kFpamPlugin) return items;
  // The companions: a range of [-1, 1] for the hysteresis branch; none for the pressure's rate. (Through `items`:
  // clang before 16 cannot capture structured bindings.)
  const auto add_companions = [&items, &device](std::string_view suffix, std::string_view companion,
                                                const char* range) {
    for (std::size_t i = 0; i < kMuscleNames.size(); ++i) {
      const std::string name = kMuscleNames[i] + std::string(suffix);
      items.custom += fmt::format("    <text name=\"{}\" data=\"{}\"/>\n", plugin::config_text_name(name), companion);
      items.actuators += fmt::format(
          "    <general name=\"{}\" {} dyntype=\"user\" gaintype=\"fixed\" gainprm=\"0\" "
          "biastype=\"user\"{}/>\n",
          name, transmission(device, i), range);
    }
  };
  if (device.hysteresis.active()) {
    add_companions(plugin::FpamConfig::kHysteresisStateSuffix, plugin::FpamConfig::kHysteresisStatePlugin,
                   " actlimited=\"true\" actrange=\"-1 1\"");
  }
  if (device.regulator.response().second_order()) {
    add_companions(plugin::FpamConfig::kPressureRateSuffix, plugin::FpamConfig::kPressureRatePlugin, "");
  }
  return items;
}

// The world's gravity. The forearm body is turned +90 deg about x, so the hand's palmar side (-z of the forearm)
// faces world +y: gravity along +y flexes the wrist; along -z it deviates the wrist ulnarly (-y of the forearm).
std::string gravity_vector(const ModelOptions& options) {
  if (options.gravity_axis == physics::WristAxis::kFlexionExtension)
    return fmt::format("0 {:.10g} 0", options.gravity + 0.0);
  return fmt::format("0 0 {:.10g}", -options.gravity);
}

}  // namespace

std::string build_model_xml(const DeviceDescription& device, const ModelOptions& options) {
  const auto& w = device.wrist;
  const auto& h = device.hand;
  const double inertia = h.mass * h.radius_of_gyration * h.radius_of_gyration;

  auto [custom, forearm_items, hand_items, tendons, actuators] = muscle_items(device, options);
  AnatomyVisuals anatomy = anatomy_visuals(device);
  // Without the drawing, without its meshes, textures, materials and table too: they took 90 % of a model's compile
  // (11 ms against 1.1 for the paper's device), and a diagnosis compiles one per replay.
  if (!options.anatomy) anatomy = AnatomyVisuals{};
  const std::string table =
      options.anatomy ? R"(    <geom name="table" type="plane" pos="0 0 -0.085" size="0.8 0.8 0.01" material="table" )"
                        R"(contype="0" conaffinity="0"/>)"
                        "\n"
                      : "";
  // MuJoCo's joint stiffness is linear and symmetric: the asymmetry and the stiffening towards the limits are
  // WristSim's, read from here.
  if (w.stiffness_asymmetry_fe != 0.0 || w.stiffness_asymmetry_ur != 0.0) {
    custom += fmt::format("    <numeric name=\"{}\" size=\"2\" data=\"{:.10g} {:.10g}\"/>\n",
                          kStiffnessAsymmetryNumeric, w.stiffness_asymmetry_fe, w.stiffness_asymmetry_ur);
  }
  if (w.limit_stiffening.torque > 0.0) {
    custom += fmt::format("    <numeric name=\"{}\" size=\"2\" data=\"{:.10g} {:.10g}\"/>\n", kLimitStiffeningNumeric,
                          w.limit_stiffening.torque, w.limit_stiffening.angle_scale);
  }

  return fmt::format(
      R"(<mujoco model="softwrist">
  <!-- Generated by softwrist from a device description (src/sim/model_builder.cc). SI units; ctrl and act in kPa.
       Hand: Winter, Biomechanics and Motor Control of Human Movement, Table 4.1. Passive wrist stiffness and
       damping: approximately Charles & Hogan 2011 (J Biomech 44:614) and Formica et al. 2012 (J Neurophysiol
       108:1158, ulnar/radial stiffer than flexion/extension). Joint ranges: biological range of motion, Table RoM. -->
  <compiler angle="radian" inertiafromgeom="false"/>
  <!-- No contacts: every geom is drawing only (contype and conaffinity 0), and without the flag MuJoCo still ran its
       collision broadphase every step (12 % of a diagnosis's time, measured with perf). A geom added to collide
       needs this flag removed and room in <size> below. -->
  <!-- The only constraint rows are the two joints' limits (and friction loss on the four tendons, where the
       diagnosis's synthetic device adds it: 6 at most): room for 16 instead of MuJoCo's default 500 rows and 100
       contacts shrinks mjData's stack from 10 MB to 25 kB, which a diagnosis allocated and cleared at each of its
       thousands of resets (12 % of a diagnosis test's time in memset, perf; the test ran a third faster). Rows
       beyond njmax would be dropped with only a warning (mjWARN_CNSTRFULL). -->
  <size njmax="16" nconmax="4"/>
  <option timestep="{timestep:.10g}" gravity="{gravity}">
    <flag contact="disable"/>
  </option>
  <visual>
    <global offwidth="1280" offheight="960"/>
    <headlight ambient="0.25 0.25 0.25" diffuse="0.35 0.35 0.35" specular="0.1 0.1 0.1"/>
  </visual>
  <asset>
{assets}  </asset>
  <custom>
{custom}  </custom>
  <worldbody>
    <light pos="0.2 -0.4 1.2" dir="-0.15 0.3 -1" diffuse="0.65 0.65 0.62" castshadow="true"/>
    <light pos="-0.4 0.6 0.8" dir="0.4 -0.6 -0.8" diffuse="0.25 0.25 0.28" castshadow="false"/>
{table}    <body name="forearm" quat="0.70710678 0.70710678 0 0">
      <inertial pos="-0.12 0 0" mass="1.2" diaginertia="0.001 0.006 0.006"/>
{forearm_geoms}{forearm_items}      <body name="hand">
        <joint name="wrist_fe" type="hinge" axis="0 1 0" limited="true" range="{ext:.10g} {flex:.10g}" stiffness="{kfe:.10g}" damping="{bfe:.10g}"/>
        <joint name="wrist_ur" type="hinge" axis="0 0 -1" limited="true" range="{rad:.10g} {uln:.10g}" stiffness="{kur:.10g}" damping="{bur:.10g}"/>
        <inertial pos="{com:.10g} 0 0" mass="{mass:.10g}" diaginertia="{i:.10g} {i:.10g} {i:.10g}"/>
{hand_geoms}{hand_items}      </body>
    </body>
  </worldbody>
  <tendon>
{tendons}  </tendon>
  <actuator>
{actuators}  </actuator>
</mujoco>
)",
      fmt::arg("timestep", options.timestep), fmt::arg("gravity", gravity_vector(options)), fmt::arg("custom", custom),
      fmt::arg("forearm_items", forearm_items), fmt::arg("hand_items", hand_items), fmt::arg("tendons", tendons),
      fmt::arg("actuators", actuators), fmt::arg("ext", -w.extension_limit), fmt::arg("flex", w.flexion_limit),
      fmt::arg("rad", -w.radial_limit), fmt::arg("uln", w.ulnar_limit), fmt::arg("kfe", w.stiffness_fe),
      fmt::arg("bfe", w.damping_fe), fmt::arg("kur", w.stiffness_ur), fmt::arg("bur", w.damping_ur),
      fmt::arg("com", h.com_distance), fmt::arg("mass", h.mass), fmt::arg("i", inertia),
      fmt::arg("assets", anatomy.assets), fmt::arg("forearm_geoms", anatomy.forearm_geoms),
      fmt::arg("hand_geoms", anatomy.hand_geoms), fmt::arg("table", table));
}

std::string with_tendon_friction(std::string xml, double friction_n) {
  const std::string tendon = "<spatial name=";
  for (auto at = xml.find(tendon); at != std::string::npos; at = xml.find(tendon, at + tendon.size())) {
    xml.insert(at + tendon.find(' ') + 1, fmt::format("frictionloss=\"{:.10g}\" ", friction_n));
  }
  return xml;
}

}  // namespace softwrist::sim
