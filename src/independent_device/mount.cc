#include "independent_device/mount.h"

#include <algorithm>
#include <cmath>

namespace softwrist::independent {

double mount_root_compliance(const MountLaw& mount) {
  return 1.0 / std::sqrt(mount.k_forearm_n_per_m2) + 1.0 / std::sqrt(mount.k_hand_n_per_m2);
}

double mount_takeup_m(const MountLaw& mount, double force_n) {
  return mount_takeup_m(mount, mount_root_compliance(mount), force_n);
}

double mount_takeup_m(const MountLaw& mount, double root_compliance, double force_n) {
  if (force_n <= 0.0) return 0.0;
  double x = root_compliance * std::sqrt(force_n);  // dx_i = sqrt(F / K_i), paper Eq. (fabric_stretching)
  if (mount.strap_compliance_m_per_n > 0.0)
    x += mount.strap_compliance_m_per_n * std::max(0.0, force_n - mount.strap_preload_n);
  if (mount.jcurve_length_m > 0.0) x += mount.jcurve_length_m * std::log1p(force_n / mount.jcurve_force_n);
  return x;
}

double glove_slide_m(const MountLaw& mount, double force_n) {
  return mount.glove_slide_m_per_n * std::max(0.0, force_n);
}

}  // namespace softwrist::independent
