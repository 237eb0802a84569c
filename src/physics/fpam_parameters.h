#pragma once
// The description of one fabric pneumatic artificial muscle (fPAM): its fabric, and its fully stretched radius
// r0 and maximum contraction ratio eps_max, either constant or per pressure (Table tensile_testing_parameters).
// Immutable once built; validated on construction.

#include <vector>

namespace softwrist::physics {

// Fabric of the fPAM wall (Section Parameter optimization; epsilon_0 from Table tensile_testing_parameters,
// where it is the eps_max of the deflated muscle).
struct FabricProperties {
  double elastic_modulus = 9.06e6;           // E [Pa]
  double thickness = 0.08e-3;                // t [m]
  double elastic_onset_contraction = 0.153;  // epsilon_0: below it the stretched fabric pulls elastically
  // kappa >= 0: the fabric stiffens as it is stretched, its pull 2 pi E t r0 (exp(kappa (eps_0 - eps)) - 1) / kappa
  // (fpam_force.h); 0 is Eqn. force's linear term. The paper's tensile test at 0 kPa is J-shaped, and it fits that
  // curve with an exponential (Section Tensile testing, Fig. TensileTest(a)); the linear term is its model's.
  double elastic_curvature = 0.0;
  bool operator==(const FabricProperties&) const = default;
};

// r0 and eps_max at one pressure.
struct FpamCoefficients {
  double radius = 0.0;           // r0 [m], fully stretched radius
  double max_contraction = 0.0;  // eps_max, contraction ratio at which the pressure force reaches zero
};

// One row of a per-pressure table.
struct FpamTableRow {
  double pressure = 0.0;  // [Pa]
  double radius = 0.0;    // r0 [m]
  double max_contraction = 0.0;
};

class FpamParameters {
 public:
  // The same r0 and eps_max at every pressure (the paper's design optimization: r0 = 1.23 cm, eps_max = 0.28).
  static FpamParameters Constant(double radius, double max_contraction, FabricProperties fabric = {});
  // A per-pressure table, rows sorted by strictly increasing pressure. Between rows r0 and eps_max are
  // interpolated linearly in pressure; outside the table they are held at the nearest row (the table spans
  // the regulators' whole 0-137 kPa range, so holding only matters for what-if pressures above it).
  static FpamParameters Table(std::vector<FpamTableRow> rows, FabricProperties fabric = {});

  // The same fabric with other rows (edited copies of rows(); one row is a constant fPAM). The one way to change an
  // fPAM's r0 or eps_max, validated as a new table is.
  FpamParameters with_rows(std::vector<FpamTableRow> rows) const;
  // The same rows with another fabric, validated.
  FpamParameters with_fabric(const FabricProperties& fabric) const;
  // Every row's r0 times radius_scale and eps_max plus max_contraction_shift (one fPAM's departure from another's
  // table), validated.
  FpamParameters scaled(double radius_scale, double max_contraction_shift) const;

  FpamCoefficients at_pressure(double pressure) const;
  const FabricProperties& fabric() const { return fabric_; }
  const std::vector<FpamTableRow>& rows() const { return rows_; }
  bool is_constant() const { return rows_.size() == 1; }

 private:
  FpamParameters(std::vector<FpamTableRow> rows, FabricProperties fabric);
  std::vector<FpamTableRow> rows_;
  FabricProperties fabric_;
};

// The largest eps_max Eqn. fiber_orientation admits: the fiber angle exists only while
// eps_max^2 - 2 eps_max + 2/3 >= 0, i.e. eps_max <= 1 - 1/sqrt(3) (about 0.423, the ideal McKibben limit).
double max_contraction_upper_bound();

void validate(const FabricProperties& fabric);
void validate(const FpamCoefficients& coefficients);

}  // namespace softwrist::physics
