#pragma once
// Planar path of one fPAM across the wrist, in the muscle's own plane and frame (after the paper's Fig.
// GeometricModel): origin at the wrist's centre of rotation O, x along the forearm towards the hand, y towards the
// muscle's side, and the angle positive in the direction the muscle pulls (flexion for the flexor, extension for
// the extensor, ...). Forearm anchor P1 = (-d1, w1); hand anchor P2 = R(theta) (d2, w2).
//
// Own computation (not the paper's closed forms): the muscle is a frictionless string over a convex wrapping
// surface fixed to the forearm. The surface is an ellipse (semi-axes a along x, b along y; a circle when a = b,
// the paper's r_w) centred at C (the paper's C = O). An affine map sends the ellipse to the unit circle and keeps
// tangency and orientation, so the tangent points from P1 and P2 are found on the unit circle; the string touches
// the surface exactly when those tangent points are out of order along the muscle's side (wrap angle > 0), which
// replaces the paper's discriminant test (Eq. straight_to_wrapping, whose printed
// D = 2ab^2 - ... should read (2ab)^2 - 4(1 + a^2)(b^2 - r_w^2)). The torque on the hand is the moment about O of
// the tension acting at P2 along the last free segment; because the surface is fixed to the forearm this equals
// -F dL/dtheta (virtual work), checked in the tests.

namespace softwrist::independent {

struct Placement {
  double d1_m = 0.0, w1_m = 0.0, d2_m = 0.0, w2_m = 0.0;
};

struct WrapSurface {
  double semi_x_m = 0.0, semi_y_m = 0.0;      // ellipse semi-axes; equal: the paper's wrist radius r_w
  double centre_x_m = 0.0, centre_y_m = 0.0;  // centre relative to the centre of rotation O
};

struct Path {
  double length_m = 0.0;
  double moment_arm_m = 0.0;  // torque / tension, positive in the muscle's own direction
  bool wrapped = false;
};

// hand_slide_m: the hand anchor displaced towards the wrist along the hand's axis (d2 -> d2 - slide).
Path muscle_path(const Placement& placement, const WrapSurface& wrap, double theta_rad, double hand_slide_m = 0.0);

}  // namespace softwrist::independent
