#pragma once
// The paper's antagonistic feedback controller (Sec. "Control system", Fig. Control): every 14 ms the angle error
// (deg) times G = 0.0083 kPa/deg is added to the agonist's pressure and subtracted from the antagonist's; the
// antagonist falls twice as fast while its pressure exceeds 13.8 kPa; all pressures start at 13.8 kPa. The
// commands are clamped to the regulators' 0-137 kPa.

#include <array>

namespace softwrist::independent {

struct PaperController {
  double gain_kpa_per_deg = 0.0083;
  double initial_kpa = 13.8;
  double threshold_kpa = 13.8;
  double max_kpa = 137.0;
  std::array<double, 4> command_kpa{};  // flexor, extensor, ulnar, radial

  // Initial pressures on the active axes; inactive muscles stay deflated.
  void reset(bool fe_active, bool ur_active);
  void update(double desired_fe_deg, double desired_ur_deg, double measured_fe_deg, double measured_ur_deg,
              bool fe_active, bool ur_active);
};

}  // namespace softwrist::independent
