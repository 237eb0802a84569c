#pragma once
// The relaxed wrist's passive torque: linear about neutral, stiffening towards the biological limits.

namespace softwrist::physics {

// The double-exponential passive joint moment of Riener & Edrich (J Biomech 32:539, 1999), as used for the wrist's
// passive moment near its limits: a torque that grows by e every `angle_scale` as the wrist nears a limit. `torque`
// is its value at each limit (0: the linear wrist, the default). The e-folding angle is not in the paper; 8 deg (its
// default, softwrist's choice, configurable in the placement file) lets it rise over the last 15-20 deg of the range,
// where relaxed wrists are reported to stiffen (Formica et al., J Neurophysiol 108:1158, 2012).
struct LimitStiffening {
  double torque = 0.0;              // [N m] at each limit, >= 0
  double angle_scale = 0.13962634;  // [rad] e-folding angle (8 deg)
};

// The stiffening's torque [N m] at `angle` [rad] about an axis whose limits are `positive_limit` (flexion, ulnar) and
// `negative_limit` (extension, radial), both positive [rad]; positive towards flexion / ulnar deviation. Offset so
// that it vanishes at neutral, where the linear stiffness alone holds:
//   tau = -A [exp((angle - l+)/s) - exp((-l- - angle)/s)] + A [exp(-l+/s) - exp(-l-/s)]
// Past a limit it stays at its value there: the joint stop takes over (MuJoCo's limit, the statics' scan end), and an
// exponential without bound would only make the simulation stiff.
double limit_stiffening_torque(const LimitStiffening& stiffening, double positive_limit, double negative_limit,
                               double angle);

// A relaxed wrist stiffer towards one side than the other (beyond the paper's linear wrist: passive wrist moments
// differ between flexion and extension and between ulnar and radial deviation, Formica et al. 2012): the stiffness
// k (1 + a) towards the positive direction (flexion, ulnar) and k (1 - a) towards the other. The torque beyond
// -k angle, -k a |angle| [N m]; |a| at most kMaxStiffnessAsymmetry (a side of at least a tenth of k).
inline constexpr double kMaxStiffnessAsymmetry = 0.9;
inline double stiffness_asymmetry_torque(double stiffness, double asymmetry, double angle) {
  return -stiffness * asymmetry * (angle < 0.0 ? -angle : angle);
}

// The relaxed wrist's whole passive torque [N m] about one axis: -stiffness angle, its asymmetry and the stiffening.
double relaxed_wrist_torque(double stiffness, const LimitStiffening& stiffening, double positive_limit,
                            double negative_limit, double angle, double asymmetry = 0.0);

}  // namespace softwrist::physics
