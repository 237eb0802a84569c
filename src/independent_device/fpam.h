#pragma once
// Static force law of one fabric pneumatic artificial muscle (fPAM).
//
// Nominal form: the paper's Eq. (force) -- the ideal McKibben term of Tondu & Lopez (2000) plus linear fabric
// elasticity -- with the fibre angle taken per pressure from the pressure-dependent maximum contraction (paper Eq.
// (fiber_orientation), Table tensile_testing_parameters). Read differently from the print:
//  * the printed pressure term pi P r0^2 (1/sin^2 a0 - 3(1-e)^2/tan^2 a0) is negative for every fibre angle below
//    54.7 deg at e = 0, i.e. it would push. The McKibben law (Chou & Hannaford 1996; Tondu & Lopez 2000) is
//    F = pi r0^2 P (3(1-e)^2/tan^2 a0 - 1/sin^2 a0), which is what Eq. (fiber_orientation) solves for F = 0 (that
//    equation is consistent with either sign). We use the tensile-positive McKibben sign.
//  * a muscle cannot push: past its maximum contraction the pressure term is zero (slack), not negative.
// Forms of the `fpam_params` effects live here too (aged fabric, Tondu-Lopez end effect, exponential fabric).

#include <array>

namespace softwrist::independent {

struct FpamLaw {
  // Paper Table tensile_testing_parameters (the flexor fPAM): pressures, fitted maximum contraction, fitted r0.
  std::array<double, 5> table_pressure_kpa{0.0, 34.0, 68.0, 103.0, 137.0};
  std::array<double, 5> table_max_contraction{0.153, 0.303, 0.296, 0.301, 0.277};
  std::array<double, 5> table_radius_m{0.0123, 0.0127, 0.0122, 0.0119, 0.0126};
  double slack_contraction = 0.153;  // epsilon_0: the deflated fPAM pulls below it (paper: e_max at 0 kPa)
  double modulus_pa = 9.06e6;        // fabric elastic modulus E (paper Sec. "Parameter optimization")
  double thickness_m = 0.08e-3;      // fabric thickness t (manufacturer's value quoted by the paper)

  // Device-to-device variation (a real fPAM is never the table's).
  double radius_scale = 1.0;
  double max_contraction_offset = 0.0;

  // fpam_params: aged_fabric -- the fabric has crept: larger radius, and a maximum contraction lowered in
  // proportion to pressure (hoop strain of the crept bias weave grows with P r, so the fibres scissor less).
  double aged_radius_gain = 0.0;
  double aged_contraction_drop_at_max = 0.0;  // drop of e_max at 137 kPa
  // fpam_params: tondu_end_effect -- Tondu & Lopez (2000) factor k on the contraction, (1 - k e)^2, for the
  // tied-off conical ends that do not contract like the cylindrical body.
  double tondu_end_factor = 1.0;
  // fpam_params: exponential_fabric -- the J-shaped fabric stretch curve the paper itself fitted at 0 kPa
  // (exponential, Sec. "Measurement of the fPAM force"), added to the linear term: A (exp(x/s) - 1 - x/s),
  // x = e0 - e, scaled so it adds `exponential_force_at_full_stretch_n` at e = 0.
  double exponential_force_at_full_stretch_n = 0.0;
  double exponential_strain_scale = 0.03;
};

// Pressure-dependent maximum contraction (piecewise linear in pressure through the table).
double max_contraction(const FpamLaw& law, double pressure_kpa);
// Fully stretched radius r0 at this pressure [m].
double fpam_radius_m(const FpamLaw& law, double pressure_kpa);
// The pressure-dependent constants of the law at one pressure (computed once per pressure, used for many lengths).
struct FpamAtPressure {
  double pressure_pa = 0.0;
  double radius_m = 0.0;
  double max_contraction = 0.0;
  double a = 0.0, b = 0.0;    // 3 / tan^2 a0 and 1 / sin^2 a0
  double area_force_n = 0.0;  // pi r0^2 P: the scale of pressure-borne forces (and of fibre friction)
  double exponential_amplitude_n = 0.0;
};
FpamAtPressure fpam_at_pressure(const FpamLaw& law, double pressure_pa);
double fpam_force_n(const FpamLaw& law, const FpamAtPressure& at, double contraction);
// Static tensile force [N] (>= 0) at contraction e = (L0 - L) / L0 and gauge pressure [Pa].
double fpam_force_n(const FpamLaw& law, double contraction, double pressure_pa);

}  // namespace softwrist::independent
