#pragma once
// The paper's parameter tables, in SI units, each named after the table it comes from. Values the paper gives
// only in figures are not here; where softwrist needs such a value it is chosen, cited and configurable where it
// is used.

#include <array>
#include <string_view>

#include "physics/muscle_torque.h"
#include "physics/units.h"

namespace softwrist::physics::paper {

// The regulators' 0-137 kPa range (Section Exosuit Prototype) is physics::kRegulatorMaxPressure (exosuit_layout.h).
// The five pressure levels of the tensile and torque measurements.
inline constexpr std::array<double, 5> kMeasurementPressures = {0.0, 34e3, 68e3, 103e3, 137e3};  // [Pa]

// Table tensile_testing_parameters: the flexor fPAM, r0 and eps_max "calculated" per pressure (the row used by
// the model; the measured r0 = 1.02 cm did not fit the tensile data). L0 = 34.0 cm on the tensile rig.
FpamParameters tensile_fpam();
inline constexpr double kTensileRestLength = 0.340;  // [m]

// Section Parameter optimization: r0 = 1.23 cm, eps_max = 0.28 (137 kPa in Naclerio et al.).
FpamParameters design_fpam();

// Table torque_measurement_parameters: the flexor on the torque-measurement rig (L0 = 32.0 cm, r_w = 3.99 cm,
// K1 = -43.36, K2 = -1097.50 N/cm^2) with the Table tensile_testing_parameters fPAM.
Muscle torque_measurement_flexor(StretchMode stretch_mode);

// Table RoM: the four muscles' placements and measured L0, the measured exosuit and biological ranges (mean and
// STD of three trials) and the model error (modeled limit - measured exosuit limit).
struct RomEntry {
  std::string_view direction;  // "flexion", "extension", "ulnar", "radial"
  Placement placement;
  double rest_length;  // [m]
  double exosuit_deg, exosuit_std_deg;
  double biological_deg, biological_std_deg;
  double model_error_deg;
  // The paper's modeled limit, which the table gives only as measured + error.
  double paper_modeled_limit_deg() const { return exosuit_deg + model_error_deg; }
};
const std::array<RomEntry, 4>& rom_table();

// Table RoM does not state r_w. The modeled limits all fall in the straight-line regime, where r_w does not enter,
// so any r_w below every mount distance gives the same limits; we use the 2 cm measured on the user's wrist
// (Section Parameter optimization). The ulnar muscle's hand mount (R2 = 3.54 cm) rules out the torque rig's
// 3.99 cm.
inline constexpr double kRomWristRadius = 0.02;  // [m]
// "We assumed that the fPAM parameters r0 and eps_max are the same as for the measured flexor fPAM at 137 kPa".
FpamParameters rom_fpam();
Muscle rom_muscle(const RomEntry& entry);

// Section Parameter optimization and Table optimized_parameters: the optimized placement of the flexor for the
// example user, r_w = 2 cm, and L0 from Eqn. length at the maximal extension angle -65.4 deg.
inline constexpr Placement kOptimizedPlacement{.d1 = 0.22, .w1 = 0.035, .d2 = 0.09, .w2 = 0.015};
inline constexpr double kDesignWristRadius = 0.02;                       // [m]
inline constexpr double kDesignMaxExtension = units::deg_to_rad(-65.4);  // [rad]
Muscle design_optimum_flexor();

}  // namespace softwrist::physics::paper
