#include "physics/fpam_parameters.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "physics/errors.h"
#include "physics/plausible_ranges.h"

namespace softwrist::physics {

double max_contraction_upper_bound() { return 1.0 - 1.0 / std::sqrt(3.0); }

void validate(const FabricProperties& fabric) {
  require_positive("elastic_modulus E [Pa]", fabric.elastic_modulus);
  require(fabric.elastic_modulus <= plausible::kMaxElasticModulus, "elastic_modulus E [Pa]", fabric.elastic_modulus,
          "must be at most 1e12 (no fabric is stiffer than steel)");
  require_positive("thickness t [m]", fabric.thickness);
  require(fabric.thickness <= plausible::kMaxThickness, "thickness t [m]", fabric.thickness,
          "must be at most 0.01 (a fabric wall)");
  require(std::isfinite(fabric.elastic_onset_contraction) && fabric.elastic_onset_contraction >= 0.0 &&
              fabric.elastic_onset_contraction < 1.0,
          "elastic_onset_contraction epsilon_0", fabric.elastic_onset_contraction, "must lie in [0, 1)");
  require(std::isfinite(fabric.elastic_curvature) && fabric.elastic_curvature >= 0.0 &&
              fabric.elastic_curvature <= plausible::kMaxElasticCurvature,
          "elastic_curvature kappa", fabric.elastic_curvature, "must lie in [0, 200] (e-folding over 0.5 % strain)");
}

void validate(const FpamCoefficients& coefficients) {
  require_positive("radius r0 [m]", coefficients.radius);
  require(coefficients.radius <= plausible::kMaxRadius, "radius r0 [m]", coefficients.radius, "must be at most 1");
  const double eps = coefficients.max_contraction;
  require(std::isfinite(eps) && eps > 0.0 && eps < 1.0, "max_contraction eps_max", eps, "must lie in (0, 1)");
  require(eps < max_contraction_upper_bound(), "max_contraction eps_max", eps,
          "must be below 1 - 1/sqrt(3) = 0.4226, where Eqn. fiber_orientation has no real fiber angle");
}

FpamParameters::FpamParameters(std::vector<FpamTableRow> rows, FabricProperties fabric)
    : rows_(std::move(rows)), fabric_(fabric) {
  validate(fabric_);
  if (rows_.empty()) throw InvalidParameter("fPAM parameter table: needs at least one row");
  for (std::size_t i = 0; i < rows_.size(); ++i) {
    const auto& row = rows_[i];
    require_non_negative("fPAM table row " + std::to_string(i) + " pressure [Pa]", row.pressure);
    validate(FpamCoefficients{row.radius, row.max_contraction});
    if (i > 0) {
      require(row.pressure > rows_[i - 1].pressure, "fPAM table row " + std::to_string(i) + " pressure [Pa]",
              row.pressure, "rows must have strictly increasing pressure");
    }
  }
}

FpamParameters FpamParameters::Constant(double radius, double max_contraction, FabricProperties fabric) {
  return FpamParameters({FpamTableRow{0.0, radius, max_contraction}}, fabric);
}

FpamParameters FpamParameters::Table(std::vector<FpamTableRow> rows, FabricProperties fabric) {
  return FpamParameters(std::move(rows), fabric);
}

FpamParameters FpamParameters::with_rows(std::vector<FpamTableRow> rows) const {
  return FpamParameters(std::move(rows), fabric_);
}

FpamParameters FpamParameters::with_fabric(const FabricProperties& fabric) const {
  return FpamParameters(rows_, fabric);
}

FpamParameters FpamParameters::scaled(double radius_scale, double max_contraction_shift) const {
  std::vector<FpamTableRow> rows = rows_;
  for (auto& row : rows) {
    row.radius *= radius_scale;
    row.max_contraction += max_contraction_shift;
  }
  return with_rows(std::move(rows));
}

FpamCoefficients FpamParameters::at_pressure(double pressure) const {
  require_non_negative("pressure [Pa]", pressure);
  if (pressure <= rows_.front().pressure) return {rows_.front().radius, rows_.front().max_contraction};
  if (pressure >= rows_.back().pressure) return {rows_.back().radius, rows_.back().max_contraction};
  const auto upper = std::upper_bound(rows_.begin(), rows_.end(), pressure,
                                      [](double p, const FpamTableRow& row) { return p < row.pressure; });
  const auto lower = upper - 1;
  const double s = (pressure - lower->pressure) / (upper->pressure - lower->pressure);
  return {lower->radius + s * (upper->radius - lower->radius),
          lower->max_contraction + s * (upper->max_contraction - lower->max_contraction)};
}

}  // namespace softwrist::physics
