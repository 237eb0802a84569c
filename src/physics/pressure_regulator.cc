#include "physics/pressure_regulator.h"

#include <array>
#include <cmath>

namespace softwrist::physics {
namespace {

using Matrix2 = std::array<std::array<double, 2>, 2>;

Matrix2 multiply(const Matrix2& a, const Matrix2& b) {
  Matrix2 c{};
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j) c[i][j] = a[i][0] * b[0][j] + a[i][1] * b[1][j];
  return c;
}

// exp(M) by scaling and squaring with a Taylor series (Moler & Van Loan, SIAM Rev. 45:3, 2003, method 3): M scaled by
// 2^-k to a norm below 1/2, where 16 terms are exact to double precision, then squared k times. A stiff M (a fast
// second pole) only costs more squarings.
Matrix2 exponential(Matrix2 m) {
  const double norm = std::max(std::abs(m[0][0]) + std::abs(m[0][1]), std::abs(m[1][0]) + std::abs(m[1][1]));
  const int squarings = norm > 0.5 ? static_cast<int>(std::ceil(std::log2(norm / 0.5))) : 0;
  const double scale = std::ldexp(1.0, -squarings);
  for (auto& row : m)
    for (double& v : row) v *= scale;
  Matrix2 sum{{{1.0, 0.0}, {0.0, 1.0}}};
  Matrix2 term = sum;
  for (int n = 1; n <= 16; ++n) {
    term = multiply(term, m);
    for (auto& row : term)
      for (double& v : row) v /= n;
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 2; ++j) sum[i][j] += term[i][j];
  }
  for (int k = 0; k < squarings; ++k) sum = multiply(sum, sum);
  return sum;
}

}  // namespace

double RegulatorResponse::time_constant_towards(double error) const {
  return error < 0.0 && vent_time_constant > 0.0 ? vent_time_constant : time_constant;
}

double pressure_rate(const RegulatorResponse& response, double commanded, double pressure) {
  const double error = commanded - pressure;
  return error / response.time_constant_towards(error);
}

RegulatedPressure regulator_step(const RegulatorResponse& response, RegulatedPressure state, double commanded,
                                 double dt) {
  const double error = state.pressure - commanded;  // e = p - u obeys the homogeneous equation while u is held
  const double tau = response.time_constant_towards(-error);
  if (!response.second_order()) {
    const double pressure = commanded + error * std::exp(-dt / tau);
    return {pressure, (commanded - pressure) / tau};
  }
  // d/dt (e, de/dt) = A (e, de/dt), A = [[0, 1], [-1/tau2^2, -tau/tau2^2]].
  const double inverse_square = 1.0 / (response.second_order_time * response.second_order_time);
  const Matrix2 step = exponential({{{0.0, dt}, {-inverse_square * dt, -tau * inverse_square * dt}}});
  return {commanded + step[0][0] * error + step[0][1] * state.rate, step[1][0] * error + step[1][1] * state.rate};
}

}  // namespace softwrist::physics
