#pragma once
// Compliance of the anchors: the elbow band (forearm, index 1) and the glove (hand, index 2) give way under the
// muscle's tension, so the muscle is shorter than the anchor-to-anchor path by the "take-up" of the mounts.
//
// Nominal: the paper's Eq. (fabric_stretching), F = K_i dx_i^2, with |K_i| from Table torque_measurement_parameters
// (the table's negative sign only states that the anchors move towards each other, against the path).
// mount_stretch forms add, in series: a linear strap with preload (elastic band pre-tensioned on donning), a
// strap that stiffens (J-curve of woven fabric and soft tissue, F = F_s (exp(dx/x_s) - 1), Fung 1967), or a glove
// that shears along the hand's axis (Hooke law of the skin-glove interface), which moves the hand anchor and so the
// moment arm, not only the length.

namespace softwrist::independent {

struct MountLaw {
  double k_forearm_n_per_m2 = 43.36e4;  // |K1| = 43.36 N/cm^2 (paper Table torque_measurement_parameters)
  double k_hand_n_per_m2 = 1097.5e4;    // |K2| = 1097.5 N/cm^2
  // mount_stretch: strap_linear_preload
  double strap_compliance_m_per_n = 0.0;
  double strap_preload_n = 8.0;
  // mount_stretch: strap_stiffening
  double jcurve_length_m = 0.0;
  double jcurve_force_n = 4.0;
  // mount_stretch: glove_slide
  double glove_slide_m_per_n = 0.0;
};

// Shortening of the muscle [m] by the mounts along the path at tension force_n.
double mount_takeup_m(const MountLaw& mount, double force_n);
// The same with the square-root law's coefficient 1/sqrt(K1) + 1/sqrt(K2) computed once (hot loop).
double mount_root_compliance(const MountLaw& mount);
double mount_takeup_m(const MountLaw& mount, double root_compliance, double force_n);
// Displacement of the hand anchor towards the wrist along the hand's axis [m].
double glove_slide_m(const MountLaw& mount, double force_n);

}  // namespace softwrist::independent
