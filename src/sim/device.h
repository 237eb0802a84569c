#pragma once
// The description of one exosuit on one arm: where each of the four fPAMs is mounted, which fPAM it is, how its
// mounts stretch, the pressure regulators, and the relaxed wrist and hand it moves. Read from a placement file
// (JSON, documented in docs/placement-file.md); the MuJoCo model is generated from it (model_builder.h).

#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include "physics/exosuit_layout.h"
#include "physics/fpam_hysteresis.h"
#include "physics/muscle_torque.h"
#include "physics/pressure_regulator.h"
#include "physics/relaxed_wrist.h"
#include "physics/units.h"

namespace softwrist::sim {

// The four muscles, in the order of the model's tendons and actuators (physics/exosuit_layout.h).
using physics::kExtensor;
using physics::kFlexor;
using physics::kMuscleNames;
using physics::kRadial;
using physics::kUlnar;
using physics::MuscleIndex;
// The muscle of that name (kMuscleNames), or nullopt.
std::optional<MuscleIndex> muscle_from_name(std::string_view name);

struct MuscleMount {
  physics::Placement placement;  // in the muscle's own plane (torque_geometry.h)
  double rest_length = 0.0;      // L0 [m]
  double wrist_radius = 0.0;     // r_w [m] of the wrist surface this muscle wraps around
  // That surface's centre relative to the joint and its shape (torque_geometry.h); the paper's: a circle about it.
  physics::WrapSurface wrap_surface;
  // This muscle's fPAM against the device's table (`fpam`, the tested one's): each muscle is cut and sealed on its
  // own, so its r0 and eps_max differ a little from the table's. 1 and 0: the table's own.
  double fpam_radius_scale = 1.0;
  double fpam_max_contraction_shift = 0.0;
};

// The relaxed wrist and the hand (cited in docs/placement-file.md and the generated model).
struct PassiveWrist {
  double stiffness_fe = 1.0;  // [N m/rad] flexion/extension (Charles & Hogan 2011, J Biomech 44:614; approx.)
  double stiffness_ur = 1.6;  // [N m/rad] ulnar/radial, stiffer than FE (Formica et al. 2012, J Neurophysiol)
  double damping_fe = 0.03;   // [N m s/rad] (Charles & Hogan 2011; approx.)
  double damping_ur = 0.04;   // [N m s/rad]
  // Biological range of motion, Table RoM [rad]: joint limits of the model.
  double flexion_limit = units::deg_to_rad(80.9);
  double extension_limit = units::deg_to_rad(56.0);
  double ulnar_limit = units::deg_to_rad(39.1);
  double radial_limit = units::deg_to_rad(23.2);
  // Stiffer towards one side than the other, k (1 + a) towards flexion / ulnar and k (1 - a) towards extension /
  // radial (physics/relaxed_wrist.h); 0 by default, the paper's wrist being linear.
  double stiffness_asymmetry_fe = 0.0;
  double stiffness_asymmetry_ur = 0.0;
  // Stiffening towards those limits (physics/relaxed_wrist.h); none by default, the paper's wrist being linear.
  physics::LimitStiffening limit_stiffening;
};

struct Hand {
  // Winter, Biomechanics and Motor Control of Human Movement (4th ed., Table 4.1): hand mass 0.006 of body mass,
  // centre of mass 0.506 of the wrist-to-knuckle length, radius of gyration 0.297 of it about the centre of mass.
  // For a 75 kg adult with an 0.19 m hand: 0.45 kg, 0.096 m, 0.056 m.
  double mass = 0.45;                 // [kg]
  double com_distance = 0.096;        // [m] from the wrist joint centre along the hand
  double radius_of_gyration = 0.056;  // [m]
  double length = 0.19;               // [m], drawn
};

struct Regulator {
  double max_pressure = physics::kRegulatorMaxPressure;  // [Pa]
  // The paper gives no regulator dynamics. 0.1 s is an assumed first-order time constant for a closed-loop
  // regulator filling a ~0.1 L fPAM through 6.35 mm tubing; the gap diagnosis's regulator_lag effect fits it.
  double time_constant = 0.1;  // [s]
  // While venting, where it differs (0: time_constant). A regulator fills from the supply and vents through its
  // exhaust, whose flow at low gauge pressure is subsonic and weaker (ISO 6358; Beater, Pneumatic Drives, 2007, ch. 3),
  // so real ones often empty a muscle more slowly than they fill it; the diagnosis's regulator_lag fits the ratio.
  double vent_time_constant = 0.0;  // [s]
  // The second time tau2 of a second-order response (physics/pressure_regulator.h: tau2^2 p'' + tau p' + p = u);
  // 0, the default, is the first-order lag. The diagnosis's regulator_lag fits it.
  double second_order_time = 0.0;  // [s]

  physics::RegulatorResponse response() const { return {time_constant, vent_time_constant, second_order_time}; }
};

// How a muscle's length follows the wrist in the MuJoCo model (plugins/fpam/fpam_config.h, FpamConfig::PlanarPath).
// spatial: a spatial tendon between the mounts, over the wrap cylinder, routed by MuJoCo in 3D: a muscle of one axis
// also acts on the other (a tensed flexor pushes the hand further from the neutral in deviation, its mounts off the
// deviation axis) and its moment arm shrinks as the wrist turns about the other axis. planar: each muscle acts on its
// own joint through the paper's 2D torque model (Eqns. tau1, tau2) at that joint's angle, as the paper and the
// analytic model have it; the tendon is then drawn only. The two agree when the other joint is at zero.
enum class Routing { kSpatial, kPlanar };
const char* to_string(Routing routing);
std::optional<Routing> parse_routing(std::string_view text);

struct DeviceDescription {
  std::array<MuscleMount, 4> muscles;
  Routing routing = Routing::kSpatial;
  // The table of the tested fPAM (Table tensile_testing_parameters), shared by the four muscles as in Section Range of
  // motion, each muscle's own r0 and eps_max relative to it (MuscleMount::fpam_radius_scale, fpam_of).
  physics::FpamParameters fpam;
  physics::FpamHysteresis hysteresis;  // the fabric's, shared too; none by default (the paper's static law)
  physics::StretchMode stretch_mode = physics::StretchMode::kNone;
  physics::MountStiffness mount_stiffness;
  Regulator regulator;
  PassiveWrist wrist;
  Hand hand;

  // The physics-core description of muscle i, for the analytic model.
  physics::Muscle muscle(int index) const;
  // The length-to-force law of a muscle mounted as `mount` (this device's fPAM and mounts): what its plugin holds.
  physics::MuscleLaw muscle_law(const MuscleMount& mount) const;
  // That mount's muscle's own fPAM: the table with its r0 scale and eps_max shift.
  physics::FpamParameters fpam_of(const MuscleMount& mount) const;
};

// The paper's device: the flexor of Table torque_measurement_parameters (with its r_w = 3.99 cm and K1, K2), the
// extensor, ulnar and radial muscles of Table RoM (r_w = 2 cm, the user's wrist), the fPAM of Table
// tensile_testing_parameters, self-consistent stretching.
DeviceDescription paper_device();
// The range-of-motion device: all four muscles of Table RoM (placements and measured L0) on the user's 2 cm wrist,
// the 137 kPa fPAM of Section Range of motion, and the torque rig's mount stiffness (Table
// torque_measurement_parameters, the only K the paper measured) with self-consistent stretching.
DeviceDescription rom_device();

// The largest joint angle [rad] muscle `index` turns through: its axis's larger biological limit (flexion/extension
// for the flexor and extensor, ulnar/radial deviation for the others; PassiveWrist) and a margin of 15 deg, as far as
// the relaxed wrist's stiffening lets the hand go past its limit (a few degrees) and beyond it the torque rig's last
// held angle (90 deg of flexion, against the 80.9 deg limit of Table RoM).
double muscle_reach(const DeviceDescription& device, int index);

// Throws physics::InvalidParameter, naming the muscle, where a muscle's hand mount comes inside its wrist surface (an
// ellipse, or a circle off the joint's centre) within its reach (physics::hand_mount_clearance).
void check_hand_mount_clearance(const DeviceDescription& device);

// Reads a placement file. Errors throw std::runtime_error("<file>: <field>: <problem>").
DeviceDescription load_device(const std::filesystem::path& path);
DeviceDescription parse_device(const std::string& json_text, const std::string& source_name);
// The placement file that load_device reads back to the same description (to within the rounding of the cm <-> m
// conversions, ~1e-16 relative).
std::string device_to_json(const DeviceDescription& device);

}  // namespace softwrist::sim
