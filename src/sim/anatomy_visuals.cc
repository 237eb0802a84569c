#include "sim/anatomy_visuals.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <numbers>

#include <fmt/format.h>

#include "physics/units.h"
#include "sim/model_builder.h"

namespace softwrist::sim {
namespace {

using Vec3 = std::array<double, 3>;
constexpr double kReferenceHandLength = 0.19;  // [m] the sizes below are for this hand (Hand::length's default)

// Matte skin, the glove's and band's dark fabric, the IMUs' boards, the stand-offs' grey plastic, a checkered
// table and a light sky. None is red or blue: those colours mean pressure (report/scene_style.h).
constexpr const char* kMaterials =
    R"(    <texture name="sky" type="skybox" builtin="gradient" rgb1="0.95 0.96 0.97" rgb2="0.66 0.69 0.74" width="256" height="256"/>
    <texture name="table" type="2d" builtin="checker" rgb1="0.84 0.83 0.80" rgb2="0.77 0.76 0.73" width="256" height="256"/>
    <material name="table" texture="table" texrepeat="12 12"/>
    <material name="skin" rgba="0.92 0.74 0.62 1" specular="0.15" shininess="0.2"/>
    <material name="glove" rgba="0.34 0.37 0.42 1" specular="0.05"/>
    <material name="band" rgba="0.26 0.28 0.31 1" specular="0.05"/>
    <material name="imu" rgba="0.10 0.42 0.28 1" specular="0.4"/>
    <material name="standoff" rgba="0.80 0.80 0.76 1"/>
)";

// Drawing attributes shared by every anatomy geom: no contact, no mass, drawn in group 1.
constexpr const char* kVisualOnly = R"(contype="0" conaffinity="0" mass="0" group="1")";

struct CrossSection {
  double half_width = 0.0;      // along y (radial/ulnar) [m]
  double half_thickness = 0.0;  // along z (dorsal/palmar) [m]
};
using Profile = std::function<CrossSection(double x)>;

std::string v3(const Vec3& v) { return fmt::format("{:.5g} {:.5g} {:.5g}", v[0] + 0.0, v[1] + 0.0, v[2] + 0.0); }
Vec3 add(const Vec3& a, const Vec3& b, double scale = 1.0) {
  return {a[0] + scale * b[0], a[1] + scale * b[1], a[2] + scale * b[2]};
}

// A closed tube along x through `stations`, each cross-section a superellipse (exponent 2: an ellipse; larger:
// flatter sides), with flat caps: vertices and counter-clockwise faces (outward normals) for an inline <mesh>.
std::string tube_mesh(const std::string& name, const std::vector<double>& stations, const Profile& profile,
                      double exponent) {
  constexpr int kAround = 24;
  const auto clean = [](double v) { return std::abs(v) < 1e-9 ? 0.0 : v; };  // no "1e-18" for a zero
  std::string vertices, faces;
  for (double x : stations) {
    const CrossSection c = profile(x);
    for (int i = 0; i < kAround; ++i) {
      const double angle = 2.0 * std::numbers::pi * i / kAround;
      const auto shape = [&](double v) { return std::copysign(std::pow(std::abs(v), 2.0 / exponent), v); };
      vertices += fmt::format("{:.4g} {:.4g} {:.4g} ", x, clean(c.half_width * shape(std::cos(angle))),
                              clean(c.half_thickness * shape(std::sin(angle))));
    }
  }
  const int rings = static_cast<int>(stations.size());
  const int first_centre = rings * kAround;
  vertices += fmt::format("{:.4g} 0 0 {:.4g} 0 0", stations.front(), stations.back());
  for (int k = 0; k + 1 < rings; ++k) {
    for (int i = 0; i < kAround; ++i) {
      const int a = k * kAround + i, b = k * kAround + (i + 1) % kAround;
      faces += fmt::format("{} {} {} {} {} {} ", a, b, a + kAround, b, b + kAround, a + kAround);
    }
  }
  const int last = (rings - 1) * kAround;
  for (int i = 0; i < kAround; ++i) {
    const int next = (i + 1) % kAround;
    faces += fmt::format("{} {} {} {} {} {} ", first_centre, next, i, first_centre + 1, last + i, last + next);
  }
  return fmt::format("    <mesh name=\"{}\" vertex=\"{}\" face=\"{}\"/>\n", name, vertices, faces);
}

std::vector<double> linspace(double from, double to, int n) {
  std::vector<double> x(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) x[static_cast<std::size_t>(i)] = from + (to - from) * i / (n - 1);
  return x;
}

// How far the surface reaches along a muscle's side.
double extent(const CrossSection& c, const Vec3& side) {
  return std::abs(side[1]) * c.half_width + std::abs(side[2]) * c.half_thickness;
}

// The factor (<= 1) that keeps each muscle's mount, at (x, w) on its side, at least 2 mm outside the surface.
double clearance_scale(const Profile& profile, const std::array<std::pair<double, double>, 4>& x_and_w) {
  double scale = 1.0;
  for (std::size_t i = 0; i < x_and_w.size(); ++i) {
    const double reach = extent(profile(x_and_w[i].first), kMuscleSides[i]);
    if (reach > 0.0) scale = std::min(scale, std::max(0.3, (x_and_w[i].second - 0.002) / reach));
  }
  return scale;
}

Profile scaled(const Profile& profile, double scale) {
  return [profile, scale](double x) {
    const CrossSection c = profile(x);
    return CrossSection{c.half_width * scale, c.half_thickness * scale};
  };
}

// Where a mount stands off the surface, a post from the surface to it (the paper's 3D-printed stand-off,
// Fig. EndpointAttachment(c)); the mount's marker itself is its site (model_builder.cc).
std::string mount_geoms(const std::string& name, const Vec3& mount, const Vec3& side, double surface) {
  const double standoff = std::abs(mount[1] * side[1] + mount[2] * side[2]) - surface;
  std::string geoms;
  if (standoff > 0.003) {
    const Vec3 base = add({mount[0], 0, 0}, side, surface);
    geoms += fmt::format(
        "      <geom name=\"{}_standoff\" type=\"capsule\" fromto=\"{} {}\" size=\"0.0025\" "
        "material=\"standoff\" {}/>\n",
        name, v3(base), v3(mount), kVisualOnly);
  }
  return geoms;
}

struct Finger {
  const char* name;
  Vec3 knuckle;                    // MCP joint at the reference hand length [m]
  double spread_deg;               // about the palm's normal, radial positive
  std::array<double, 3> length;    // phalanges, fractions of hand length (Buchholz et al. 1992, J Biomech 25:149)
  double radius;                   // proximal phalanx [m] at the reference hand length
  std::array<double, 3> flex_deg;  // relaxed flexion at MCP, PIP, DIP (towards palmar)
};
constexpr std::array<Finger, 4> kFingers = {{
    {"index", {0.080, 0.026, -0.002}, 7.0, {0.245, 0.143, 0.097}, 0.0093, {18, 28, 14}},
    {"middle", {0.083, 0.008, -0.002}, 1.0, {0.266, 0.170, 0.108}, 0.0096, {20, 32, 15}},
    {"ring", {0.079, -0.010, -0.002}, -5.0, {0.244, 0.165, 0.107}, 0.0091, {22, 34, 16}},
    {"little", {0.071, -0.027, -0.003}, -12.0, {0.204, 0.117, 0.094}, 0.0080, {25, 36, 18}},
}};

// Direction of a phalanx: `flex` towards palmar (-z), `spread` towards radial (+y).
Vec3 phalanx_direction(double flex_deg, double spread_deg) {
  const double f = units::deg_to_rad(flex_deg), s = units::deg_to_rad(spread_deg);
  return {std::cos(f) * std::cos(s), std::cos(f) * std::sin(s), -std::sin(f)};
}

std::string digit_geoms(double hand_length) {
  const double s = hand_length / kReferenceHandLength;
  std::string geoms;
  for (const Finger& finger : kFingers) {
    Vec3 joint = {finger.knuckle[0] * s, finger.knuckle[1] * s, finger.knuckle[2] * s};
    double flex = 0.0, radius = finger.radius * s;
    for (int k = 0; k < 3; ++k) {
      flex += finger.flex_deg[static_cast<std::size_t>(k)];
      const Vec3 end = add(joint, phalanx_direction(flex, finger.spread_deg),
                           finger.length[static_cast<std::size_t>(k)] * hand_length);
      geoms += fmt::format(
          "        <geom name=\"{}_{}\" type=\"capsule\" fromto=\"{} {}\" size=\"{:.4g}\" "
          "material=\"skin\" {}/>\n",
          finger.name, k + 1, v3(joint), v3(end), radius, kVisualOnly);
      joint = end;
      radius *= 0.9;
    }
  }
  // The thumb: from the carpometacarpal joint, radial and palmar of the palm; metacarpal, proximal, distal (Buchholz
  // et al. 1992: 0.251, 0.196, 0.158 hand lengths). The metacarpal, thick, stands for the thenar eminence.
  const std::array<Vec3, 3> directions = {{{0.74, 0.55, -0.38}, {0.86, 0.36, -0.36}, {0.88, 0.14, -0.45}}};
  const std::array<double, 3> lengths = {0.251, 0.196, 0.158}, radii = {0.0135, 0.0105, 0.0095};
  Vec3 joint = {0.018 * s, 0.020 * s, -0.008 * s};
  for (std::size_t k = 0; k < 3; ++k) {
    const Vec3& d = directions[k];
    const double norm = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    const Vec3 end = add(joint, d, lengths[k] * hand_length / norm);
    geoms += fmt::format(
        "        <geom name=\"thumb_{}\" type=\"capsule\" fromto=\"{} {}\" size=\"{:.4g}\" "
        "material=\"{}\" {}/>\n",
        k + 1, v3(joint), v3(end), radii[k] * s, k == 0 ? "glove" : "skin", kVisualOnly);
    joint = end;
  }
  return geoms;
}

// An IMU (BNO055 on its board) strapped to the dorsal side at `x`, `surface` above the centre line.
std::string imu_geom(const std::string& name, double x, double surface, const std::string& indent) {
  return fmt::format(
      "{}<geom name=\"{}_imu\" type=\"box\" pos=\"{:.5g} 0 {:.5g}\" size=\"0.013 0.010 0.004\" "
      "material=\"imu\" {}/>\n",
      indent, name, x, surface + 0.004, kVisualOnly);
}

// Forearm: an ellipse of 2.9 x 1.9 cm half-axes at the wrist (a wrist circumference of 15.5 cm) widening over the
// muscle bellies to 4.3 x 3.4 cm at 70 % of the way to the elbow, then narrowing slightly (approximate adult
// anthropometry, scaled with the hand).
Profile forearm_profile(double length, double s) {
  return [length, s](double x) {
    const double t = std::clamp(-x / length, 0.0, 1.0);
    const double belly =
        t < 0.7 ? std::sin(0.5 * std::numbers::pi * t / 0.7) : 1.0 - 0.3 * std::pow((t - 0.7) / 0.3, 2);
    return CrossSection{s * (0.029 + 0.014 * belly), s * (0.019 + 0.015 * belly)};
  };
}

// Palm (in the glove): 2.9 x 1.7 cm half-axes at the wrist to 4.2 x 1.3 cm at the knuckles.
Profile palm_profile(double palm_length, double s) {
  return [palm_length, s](double x) {
    const double t = std::clamp(x / palm_length, 0.0, 1.0);
    return CrossSection{s * (0.029 + 0.013 * t), s * (0.017 - 0.004 * t)};
  };
}

}  // namespace

double drawn_forearm_length(const DeviceDescription& device) {
  double farthest = 0.0;
  for (const MuscleMount& m : device.muscles) farthest = std::max(farthest, m.placement.d1);
  return std::max(1.35 * device.hand.length, farthest + 0.02);
}

AnatomyVisuals anatomy_visuals(const DeviceDescription& device) {
  const double s = device.hand.length / kReferenceHandLength;
  const double forearm_length = drawn_forearm_length(device);
  const double palm_length = 0.41 * device.hand.length;

  std::array<std::pair<double, double>, 4> forearm_mounts, hand_mounts;
  for (std::size_t i = 0; i < device.muscles.size(); ++i) {
    const physics::Placement& p = device.muscles[i].placement;
    forearm_mounts[i] = {-p.d1, p.w1};
    hand_mounts[i] = {std::clamp(p.d2, 0.0, palm_length), p.w2};
  }
  // The elbow band, 3 mm proud of the skin: from the forearm's end to 2.5 cm past the farthest forearm mount (at
  // least 3 cm wide, and short of the wrist).
  const Profile natural_forearm = forearm_profile(forearm_length, s);
  const Profile band_over = [&](double x) {
    const CrossSection c = natural_forearm(x);
    return CrossSection{c.half_width + 0.003, c.half_thickness + 0.003};
  };
  const double forearm_scale = clearance_scale(band_over, forearm_mounts);
  const Profile forearm = scaled(natural_forearm, forearm_scale);
  const Profile band = scaled(band_over, forearm_scale);
  const Profile palm = scaled(palm_profile(palm_length, s), clearance_scale(palm_profile(palm_length, s), hand_mounts));

  double farthest_mount = 0.0;
  for (const auto& [x, w] : forearm_mounts) farthest_mount = std::min(farthest_mount, x);
  const double band_to = std::min(farthest_mount + 0.025, -0.02);
  const double band_from = std::min(-forearm_length + 0.004, band_to - 0.03);

  AnatomyVisuals v;
  v.assets = std::string(kMaterials) + tube_mesh("forearm_skin", linspace(-forearm_length, 0.0, 10), forearm, 2.0) +
             tube_mesh("elbow_band", linspace(band_from, band_to, 4), band, 2.0) +
             tube_mesh("palm_glove", linspace(-0.012, palm_length, 5), palm, 3.0);
  const CrossSection wrist = forearm(0.0);
  v.forearm_geoms = fmt::format(
      "      <geom name=\"forearm\" type=\"mesh\" mesh=\"forearm_skin\" material=\"skin\" {0}/>\n"
      "      <geom name=\"wrist\" type=\"ellipsoid\" size=\"0.012 {1:.5g} {2:.5g}\" material=\"skin\" {0}/>\n"
      "      <geom name=\"elbow_band\" type=\"mesh\" mesh=\"elbow_band\" material=\"band\" {0}/>\n",
      kVisualOnly, wrist.half_width, wrist.half_thickness);
  v.forearm_geoms +=
      imu_geom("forearm", -0.45 * forearm_length, forearm(-0.45 * forearm_length).half_thickness, "      ");
  v.hand_geoms = fmt::format("        <geom name=\"hand\" type=\"mesh\" mesh=\"palm_glove\" material=\"glove\" {}/>\n",
                             kVisualOnly);
  v.hand_geoms += imu_geom("hand", 0.5 * palm_length, palm(0.5 * palm_length).half_thickness, "        ");
  v.hand_geoms += digit_geoms(device.hand.length);
  for (std::size_t i = 0; i < kMuscleNames.size(); ++i) {
    const MuscleMount& m = device.muscles[i];
    const Vec3& side = kMuscleSides[i];
    const std::string name = kMuscleNames[i];
    v.forearm_geoms += mount_geoms(name + "_forearm", add({-m.placement.d1, 0, 0}, side, m.placement.w1), side,
                                   extent(band(-m.placement.d1), side));
    const double x2 = std::clamp(m.placement.d2, 0.0, palm_length);
    v.hand_geoms += "  " + mount_geoms(name + "_hand", add({m.placement.d2, 0, 0}, side, m.placement.w2), side,
                                       extent(palm(x2), side));
  }
  return v;
}

}  // namespace softwrist::sim
