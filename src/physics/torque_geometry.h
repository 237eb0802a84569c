#pragma once
// The 2D geometry of one fPAM across the wrist (Section Exosuit torque model, Fig. GeometricModel): its path
// length and its moment arm about the joint centre O, in the straight-line regime (Eqn. tau1) or wrapped around a
// wrist circle of radius r_w (Eqns. parameters2, length, tau2).
//
// Frame (as in the paper): O at the origin, z along the joint axis, x along the forearm towards the hand, y towards
// the muscle's side. The forearm mount is P1 = (-d1, w1); the hand mount is P2 = Rot(theta) (d2, w2). A positive
// joint angle turns the hand towards the muscle's side, i.e. in the direction this muscle pulls it (flexion for the
// flexor). The torque of a muscle pulling with force F is F * moment_arm, positive in that direction.
//
// Readings of the printed equations, checked in tests/physics/torque_geometry_test.cc:
//  - Regime. Eqn. straight_to_wrapping counts where the infinite line through P1 and P2 meets the wrist circle
//    (its printed D = 2ab^2 - ... is (2ab)^2 - 4(1+a^2)(b^2-r_w^2), the quadratic's discriminant). That line can
//    meet the circle beyond a mount point, on the far side of O, or be vertical (a undefined), so D alone does not
//    say whether the muscle itself touches the wrist. We use the sign of the wrap angle phi of Eqn. parameters2
//    instead: phi > 0 exactly when the tangent point Q2 lies past Q1 along the muscle's side of the circle, i.e.
//    when the segment P1P2 would cut into the wrist; at phi = 0 the segment is tangent (D = 0), the paper's
//    transition.
//  - Eqn. tau2 prints cos(phi - psi) and sin(phi - psi). With psi measured from y towards x (as Eqn. parameters2
//    defines it) the last wrapped point is Q2 = r_w (sin(psi + phi), cos(psi + phi)), so we use psi + phi. Then
//    the force line P2Q2 is tangent to the wrist and the wrapped moment arm is exactly r_w (the paper: "In this
//    range, the moment arm is constant"), and torque and length are continuous at the transition. The printed
//    phi - psi turns Q2 by -2 psi off the tangent point: its moment arm is still constant but a little below r_w
//    (0.44 % on the torque rig, where psi = 2.75 deg), so the torque would step by that much at the transition.
//
// Beyond the paper: the wrist surface's centre C need not be the joint centre O, nor the surface a circle
// (WrapSurface). The carpal bones the
// muscles wrap over are fixed to the hand's proximal row and the forearm's distal end, while the instantaneous centre
// of rotation of flexion/extension lies in the capitate's head and moves a few millimetres over the range (Neu, Crisco
// & Wolfe, J Biomech 34:1429, 2001; Kaufmann et al., J Hand Surg 30A:937, 2005): C is fixed in the forearm's frame, the
// hand turns about O. An elliptical surface is wrapped by the same construction in coordinates scaled to make it the
// unit circle (tangency is affine-invariant); its arc length by Gauss-Legendre quadrature. With C = O and aspect 1
// the path is the paper's exactly (tested).

#include <cmath>

namespace softwrist::physics {

// Mounting-point placement of one fPAM (Fig. GeometricModel; Tables optimized_parameters, RoM), in metres.
struct Placement {
  double d1 = 0.0;  // forearm mount P1: distance from O along the forearm's centre line
  double w1 = 0.0;  // forearm mount P1: distance from the forearm's centre line, on the muscle's side
  double d2 = 0.0;  // hand mount P2: distance from O along the hand's centre line
  double w2 = 0.0;  // hand mount P2: distance from the hand's centre line, on the muscle's side
};

// The wrist surface the muscle wraps over, in the forearm's frame of the muscle's plane (x along the forearm towards
// the hand, y towards the muscle's side): its centre C relative to the joint centre O [m], and its shape, an ellipse
// whose semi-axis across the forearm is the wrist radius r_w and whose semi-axis along it is aspect * r_w. Centre
// (0, 0) and aspect 1: the paper's circle about O. Musculoskeletal models wrap muscles over ellipsoids where a circle
// does not fit the bone's profile (Garner & Pandy, Comput Methods Biomech Biomed Engin 3:1, 2000; OpenSim's
// WrapEllipsoid): a wrist flatter along the forearm than across it has aspect > 1.
struct WrapSurface {
  double x = 0.0;
  double y = 0.0;
  double aspect = 1.0;
  bool at_joint() const { return x == 0.0 && y == 0.0; }
  bool circular() const { return aspect == 1.0; }
  bool is_papers() const { return at_joint() && circular(); }
};

enum class Regime { kStraight, kWrapping };
const char* to_string(Regime regime);

struct MusclePath {
  Regime regime = Regime::kStraight;
  double length = 0.0;         // L (Eqn. tau1) or L_w (Eqn. length) [m]
  double moment_arm = 0.0;     // torque per newton of muscle force about O [m]
  double wrap_angle = 0.0;     // phi of Eqn. parameters2 [rad]; > 0 exactly when the muscle wraps (on an ellipse:
                               // the wrapped arc's span in the ellipse's parametric angle)
  double tangent_angle = 0.0;  // psi of Eqn. parameters2 [rad]: angle from y to C->Q1, towards x
};

// Throws InvalidParameter unless the placement is finite, d1, d2 > 0, w1, w2 >= 0, r_w > 0, the aspect within
// [0.25, 4], and both mounts lie outside the wrist surface (R1, R2 > r_w for the paper's circle about O: the tangents
// of Eqn. parameters2 exist at every angle). A surface off O or elliptic: the hand mount, turning about O, comes closer
// to it as the wrist turns, at angles that may lie beyond the joint's range (an ulnar mount 3.5 cm from O above an
// ellipse of semi-axes 2 cm across and 3.7 cm along the forearm meets it at 62 deg of radial deviation); so here it is
// checked at the joint's zero, with C nearer O than the mount, and over the joint's range by whoever knows it
// (hand_mount_clearance, sim::load_device). At an angle where the mount is inside the surface the path is continued
// through the mount's foot on it (the point at its polar angle about C, in the coordinates that make the surface the
// unit circle): the arc to the foot, the distance to the mount, and the moment arm along the surface there, the limits
// of the wrapped path as the mount reaches the surface, so torque and length are continuous where it enters. Only
// continuous: inside, the moment arm is not -dL/dtheta, and where the wrap ends with the mount still inside, the
// length steps by the difference between the foot's detour and the straight segment; neither within the reach.
void validate(const Placement& placement, double wrist_radius, WrapSurface surface = {});

// The least distance of the hand mount from the surface's centre over joint angles |theta| <= max_angle [rad], in
// the coordinates that make the surface the unit circle (above 1: outside it at every such angle).
double hand_mount_clearance(const Placement& placement, double wrist_radius, WrapSurface surface, double max_angle);

// The muscle's path at a joint angle [rad], |joint_angle| <= pi.
MusclePath muscle_path(const Placement& placement, double wrist_radius, double joint_angle, WrapSurface surface = {});

// A joint angle with its cosine and sine, for loops that visit the same angles at many placements.
struct JointAngle {
  explicit JointAngle(double angle) : radians(angle), cos(std::cos(angle)), sin(std::sin(angle)) {}
  double radians, cos, sin;
};

// What of the path depends on the placement alone (validated once: R1, R2, psi and phi at zero), for loops over
// many angles at one placement (the design objective's reference angles). at(theta) == muscle_path(..., theta).
class PlacementGeometry {
 public:
  // validate(placement, wrist_radius, surface)
  PlacementGeometry(const Placement& placement, double wrist_radius, WrapSurface surface = {});
  MusclePath at(double joint_angle) const { return at(JointAngle(joint_angle)); }
  MusclePath at(const JointAngle& joint_angle) const;

 private:
  MusclePath off_centre_at(const JointAngle& joint_angle) const;  // a circle about C != O: the general construction
  MusclePath elliptic_at(const JointAngle& joint_angle) const;    // an ellipse

  Placement placement_;
  WrapSurface surface_;
  double wrist_radius_;
  // The circle's (unused on an ellipse).
  double tangent_length1_ = 0.0, tangent_length2_ = 0.0, tangent_angle_ = 0.0, wrap_angle_at_zero_ = 0.0;
  double cos_q2_at_zero_ = 0.0, sin_q2_at_zero_ = 0.0;  // of psi + phi0: Q2's polar angle is psi + phi0 - theta
};

// The joint angle [rad] at which the muscle stops wrapping: Eqn. parameters2 solved for phi = 0,
// theta* = pi/2 - (psi + acos(r_w/R2) + asin(w2/R2)). Below it the muscle wraps, above it it runs straight. For the
// paper's circle about O (WrapSurface at the joint).
double wrap_transition_angle(const Placement& placement, double wrist_radius);

// A wrapped path's tangent points, Q1 (from the forearm mount) and Q2 (from the hand mount), where its straight
// segments touch the surface, in the forearm's frame [m]: for the circle Q1 = C + r_w (sin psi, cos psi) and Q2 = C +
// r_w (sin(psi + phi), cos(psi + phi)) (Eqn. parameters2 with psi + phi, above). `path` is muscle_path's at
// `joint_angle`, wrapping.
struct TangentPoints {
  double q1x = 0.0, q1y = 0.0, q2x = 0.0, q2y = 0.0;
};
TangentPoints tangent_points(const Placement& placement, double wrist_radius, WrapSurface surface, double joint_angle,
                             const MusclePath& path);

// The circle that stands in for a non-circular surface where only circles can be wrapped (MuJoCo's cylinders): tangent
// to both straight segments of a wrapped path, so the same moment arm about O, and of the radius that makes the path
// around it as long (the wrapped arc shortcut by the circle: L(r) = |P1X| + |XP2| - 2 r tan(phi/2) + r phi, X where
// the segments' lines meet, phi the path's turn there). For a turn below 0.02 rad, the ellipse's radius of curvature
// at the arc's middle (the length then differs by under phi^3 r / 12, 1e-7 of a centimetre-size path).
struct EquivalentCircle {
  double x = 0.0, y = 0.0;  // centre, forearm frame [m]
  double radius = 0.0;      // [m]
};
// The equivalent circle of a wrapped `path` (muscle_path's) on `surface` with wrist radius r_w, the hand at
// `joint_angle`; for a straight path, the circle inscribed in the surface at its centre (the segment misses it too).
EquivalentCircle equivalent_circle(const Placement& placement, double wrist_radius, WrapSurface surface,
                                   double joint_angle, const MusclePath& path);

}  // namespace softwrist::physics
