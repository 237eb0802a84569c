#pragma once
// The length-to-force law of one fPAM muscle with its mounts: Eqn. force at the contraction ratio (L0 - L) / L0 of
// its effective length, the mounts' stretch (Eqn. fabric_stretching, mount_stretch.h) shortening the path. The one
// law that the MuJoCo plugin holds (plugins/fpam) and that Muscle embeds with its path geometry (muscle_torque.h).

#include "physics/fpam_force.h"
#include "physics/fpam_parameters.h"
#include "physics/mount_stretch.h"

namespace softwrist::physics {

struct MuscleLaw {
  FpamParameters fpam;
  double rest_length = 0.0;  // L0 [m], fully stretched length of the deflated fPAM
  StretchMode stretch_mode = StretchMode::kNone;
  MountStiffness mount_stiffness;  // used unless stretch_mode is kNone
};
// L0 in (0, 10 m] (plausible_ranges.h); the mount stiffness when the mounts stretch.
void validate(const MuscleLaw& law);

// The pull [N] and the mounts' stretch at a mount-to-mount `path_length` [m], with the force law prepared for one
// pressure from this law's fPAM (for loops over many lengths at one pressure). The law must have been validated.
StretchedForce stretched_force(const MuscleLaw& law, const FpamForceLaw& force_law, double path_length);
// What the stretch needs of a muscle beyond its force law, worked out once by a caller that evaluates it every step
// (the plugin): the mounts' compliance 1/sqrt(K1) + 1/sqrt(K2) (mount_stretch.h) and the reciprocals the closed form
// would otherwise divide by at every call.
struct StretchConstants {
  double compliance = 0.0;
  double inverse_compliance = 0.0;   // 0 where the compliance is 0 or not finite, or the law not the paper's (no
                                     // closed form there: MountStiffness::is_papers_law)
  double inverse_rest_length = 0.0;  // 1 / L0
};
StretchConstants stretch_constants(const MuscleLaw& law);  // the law must have been validated
StretchedForce stretched_force(const MuscleLaw& law, const FpamForceLaw& force_law, double path_length,
                               const StretchConstants& constants);
// The same at `pressure` [Pa]; validates the law.
StretchedForce stretched_force(const MuscleLaw& law, double path_length, double pressure);

}  // namespace softwrist::physics
