#include "physics/paper_parameters.h"

#include "physics/units.h"

namespace softwrist::physics::paper {

using units::cm_to_m;
using units::kpa_to_pa;

FpamParameters tensile_fpam() {
  return FpamParameters::Table({
      {kpa_to_pa(0), cm_to_m(1.23), 0.153},
      {kpa_to_pa(34), cm_to_m(1.27), 0.303},
      {kpa_to_pa(68), cm_to_m(1.22), 0.296},
      {kpa_to_pa(103), cm_to_m(1.19), 0.301},
      {kpa_to_pa(137), cm_to_m(1.26), 0.277},
  });
}

FpamParameters design_fpam() { return FpamParameters::Constant(cm_to_m(1.23), 0.28); }

Muscle torque_measurement_flexor(StretchMode stretch_mode) {
  return Muscle{{.fpam = tensile_fpam(),
                 .rest_length = cm_to_m(32.00),
                 .stretch_mode = stretch_mode,
                 .mount_stiffness = {.forearm = units::n_per_cm2_to_n_per_m2(-43.36),
                                     .hand = units::n_per_cm2_to_n_per_m2(-1097.50)}},
                {.d1 = cm_to_m(19.47), .w1 = cm_to_m(4.93), .d2 = cm_to_m(8.30), .w2 = cm_to_m(3.38)},
                cm_to_m(3.99)};
}

const std::array<RomEntry, 4>& rom_table() {
  static const std::array<RomEntry, 4> table = {{
      {"flexion", {cm_to_m(20.5), cm_to_m(5.7), cm_to_m(4.0), cm_to_m(4.0)}, cm_to_m(29.0), 44.5, 7.5, 80.9, 6.7, 5.3},
      {"extension",
       {cm_to_m(24.5), cm_to_m(3.7), cm_to_m(5.4), cm_to_m(4.1)},
       cm_to_m(32.0),
       38.7,
       5.2,
       56.0,
       6.8,
       20.9},
      {"ulnar", {cm_to_m(21.1), cm_to_m(7.1), cm_to_m(1.0), cm_to_m(3.4)}, cm_to_m(28.5), 26.8, 3.4, 39.1, 1.3, 16.1},
      {"radial", {cm_to_m(21.3), cm_to_m(4.8), cm_to_m(2.3), cm_to_m(6.0)}, cm_to_m(27.0), 15.9, 3.3, 23.2, 2.3, 14.0},
  }};
  return table;
}

FpamParameters rom_fpam() { return FpamParameters::Constant(cm_to_m(1.26), 0.277); }

Muscle rom_muscle(const RomEntry& entry) {
  return Muscle{{.fpam = rom_fpam(), .rest_length = entry.rest_length}, entry.placement, kRomWristRadius};
}

Muscle design_optimum_flexor() {
  return Muscle{{.fpam = design_fpam(),
                 .rest_length = rest_length_for_range(kOptimizedPlacement, kDesignWristRadius, kDesignMaxExtension)},
                kOptimizedPlacement,
                kDesignWristRadius};
}

}  // namespace softwrist::physics::paper
