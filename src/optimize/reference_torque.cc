#include "optimize/reference_torque.h"

#include <stdexcept>
#include <string>

#include "io/csv.h"
#include "optimize/cubic_spline.h"
#include "physics/units.h"

namespace softwrist::optimize {

ReferenceTorque read_reference_torque(const std::filesystem::path& path) {
  const io::CsvTable table = io::CsvTable::Read(path);
  const int angle_column = table.column("angle_deg");
  const int torque_column = table.column("torque_nm");
  if (table.row_count() < 2) throw std::runtime_error(path.string() + ": needs at least two rows of data");
  ReferenceTorque reference;
  for (std::size_t row = 0; row < table.row_count(); ++row) {
    const double angle_deg = table.number(row, angle_column);
    const double torque = table.number(row, torque_column);
    const std::string where = path.string() + ":" + std::to_string(table.line_of(row)) + ": ";
    if (angle_deg < -180.0 || angle_deg > 180.0) throw std::runtime_error(where + "angle_deg: outside -180..180");
    if (torque < 0.0) throw std::runtime_error(where + "torque_nm: negative (the torque the muscle must reach)");
    const double angle = units::deg_to_rad(angle_deg);
    if (!reference.angles.empty() && !(angle > reference.angles.back())) {
      throw std::runtime_error(where + "angle_deg: not above the previous row's (angles must increase)");
    }
    reference.angles.push_back(angle);
    reference.torques.push_back(torque);
  }
  return reference;
}

ReferenceTorque resample(const ReferenceTorque& reference, int samples) {
  if (samples < 2) throw std::invalid_argument("resample: needs at least two samples");
  const CubicSpline spline(reference.angles, reference.torques);
  ReferenceTorque result;
  const double first = reference.angles.front(), last = reference.angles.back();
  for (int i = 0; i < samples; ++i) {
    const double angle = first + (last - first) * i / (samples - 1);
    result.angles.push_back(angle);
    result.torques.push_back(spline(angle));
  }
  return result;
}

}  // namespace softwrist::optimize
