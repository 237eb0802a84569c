#pragma once
// The reference torque profile a design must reach (Section Reference biological torque): the peak biological
// torque of the user at a few wrist angles, resampled with MATLAB's spline to N points as Section Parameter
// optimization does (8 measured angles to 140 samples).

#include <filesystem>
#include <vector>

namespace softwrist::optimize {

struct ReferenceTorque {
  std::vector<double> angles;   // [rad], strictly increasing, positive in the muscle's own direction
  std::vector<double> torques;  // [N m], the torque the muscle's direction needs there
};

// Reads a CSV with columns angle_deg, torque_nm (others, e.g. torque_std_nm, are ignored). At least two rows,
// angles strictly increasing, torques finite and not negative. Errors name the file, line and column.
ReferenceTorque read_reference_torque(const std::filesystem::path& path);

// `samples` points evenly spaced over the profile's angle range, through the not-a-knot cubic spline of its points.
ReferenceTorque resample(const ReferenceTorque& reference, int samples);

}  // namespace softwrist::optimize
