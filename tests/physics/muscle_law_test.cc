// The one length-to-force law of a muscle with its mounts (physics/muscle_law.h), which the plugin holds and
// Muscle embeds.

#include "physics/muscle_law.h"

#include <vector>

#include <gtest/gtest.h>

#include "physics/errors.h"
#include "physics/muscle_torque.h"
#include "physics/paper_parameters.h"

namespace softwrist::physics {
namespace {

// Table torque_measurement_parameters' flexor: the law at the path length is the muscle's force at that angle.
TEST(MuscleLaw, IsTheMusclesForceAtItsPathLength) {
  for (const StretchMode mode : {StretchMode::kNone, StretchMode::kOneShot, StretchMode::kSelfConsistent}) {
    const Muscle muscle = paper::torque_measurement_flexor(mode);
    for (const double angle : {-0.8, 0.0, 0.6}) {
      for (const double pressure : paper::kMeasurementPressures) {
        const MuscleState state = muscle_state(muscle, angle, pressure);
        const StretchedForce law = stretched_force(muscle, state.path_length, pressure);
        EXPECT_DOUBLE_EQ(law.force, state.force) << angle << " " << pressure;
        EXPECT_DOUBLE_EQ(law.mount_stretch, state.mount_stretch);
      }
    }
  }
}

// Eqn. fabric_stretching: the mounts' stretch shortens the muscle, so it pulls less than with rigid mounts.
TEST(MuscleLaw, StretchingMountsPullLess) {
  const Muscle stretching = paper::torque_measurement_flexor(StretchMode::kSelfConsistent);
  MuscleLaw rigid = stretching;
  rigid.stretch_mode = StretchMode::kNone;
  const double length = 0.30;
  EXPECT_LT(stretched_force(stretching, length, 137e3).force, stretched_force(rigid, length, 137e3).force);
  EXPECT_GT(stretched_force(stretching, length, 137e3).mount_stretch, 0.0);
}

// The self-consistent stretch in closed form (Eqn. force is piecewise quadratic in length) is the root the iterative
// solver of mount_stretch.h finds, to 1e-10 of the force, across pressures, lengths from slack to beyond L0, on both
// sides of the elastic onset, with the paper's mounts, ten times softer ones and very stiff ones; and it satisfies
// Eqn. fabric_stretching, F = f(L - c sqrt(F)).
TEST(MuscleLaw, SelfConsistentStretchInClosedFormIsTheIterativeRoot) {
  const Muscle paper_flexor = paper::torque_measurement_flexor(StretchMode::kSelfConsistent);
  for (const double softness : {0.1, 1.0, 1e3}) {
    MuscleLaw law = paper_flexor;
    law.mount_stiffness.forearm *= softness;
    law.mount_stiffness.hand *= softness;
    for (double pressure = 0.0; pressure <= 137e3; pressure += 17.125e3) {
      const FpamForceLaw force_law(pressure, law.fpam.at_pressure(pressure), law.fpam.fabric());
      const auto at_length = [&](double l) { return force_law((law.rest_length - l) / law.rest_length); };
      for (double length = 0.15; length <= 0.40; length += 0.0025) {
        const StretchedForce closed = stretched_force(law, force_law, length);
        const StretchedForce iterative =
            solve_mount_stretch(at_length, length, law.mount_stiffness, StretchMode::kSelfConsistent);
        EXPECT_NEAR(closed.force, iterative.force, 1e-10 * (1.0 + iterative.force)) << pressure << " " << length;
        EXPECT_NEAR(closed.mount_stretch, iterative.mount_stretch, 1e-10) << pressure << " " << length;
        EXPECT_NEAR(closed.force, at_length(length - closed.mount_stretch), 1e-9 * (1.0 + closed.force));
      }
    }
  }
}

// With a J-shaped fabric the law is no quadratic where the fabric pulls: the self-consistent stretch falls back to the
// iterative solve and still satisfies F = f(L - c sqrt(F)) (Eqn. fabric_stretching).
TEST(MuscleLaw, SelfConsistentStretchWithACurvedFabricSatisfiesItsEquation) {
  MuscleLaw law = paper::torque_measurement_flexor(StretchMode::kSelfConsistent);
  std::vector<FpamTableRow> rows = law.fpam.rows();
  law.fpam = FpamParameters::Table(rows, FabricProperties{.elastic_curvature = 25.0});
  for (const double pressure : {0.0, 68e3, 137e3}) {
    const FpamForceLaw force_law(pressure, law.fpam.at_pressure(pressure), law.fpam.fabric());
    const auto at_length = [&](double l) { return force_law((law.rest_length - l) / law.rest_length); };
    for (double length = 0.28; length <= 0.40; length += 0.005) {
      const StretchedForce s = stretched_force(law, force_law, length);
      EXPECT_NEAR(s.force, at_length(length - s.mount_stretch), 1e-6 * (1.0 + s.force)) << pressure << " " << length;
      EXPECT_NEAR(s.mount_stretch, total_mount_stretch(s.force, law.mount_stiffness), 1e-9);
    }
  }
}

// A mount law of another shape than Eqn. fabric_stretching has no closed form: stretched_force (the plugin's path,
// with its StretchConstants) is the iterative root, and still the paper's closed form where the shape is the paper's.
TEST(MuscleLaw, OtherMountShapesTakeTheIterativeSolve) {
  MuscleLaw law = paper::torque_measurement_flexor(StretchMode::kSelfConsistent);
  law.mount_stiffness.exponent = 3.0;
  law.mount_stiffness.preload = 5.0;
  EXPECT_EQ(stretch_constants(law).inverse_compliance, 0.0);
  for (const double pressure : {0.0, 68e3, 137e3}) {
    const FpamForceLaw force_law(pressure, law.fpam.at_pressure(pressure), law.fpam.fabric());
    const auto at_length = [&](double l) { return force_law((law.rest_length - l) / law.rest_length); };
    for (double length = 0.28; length <= 0.40; length += 0.01) {
      const StretchedForce s = stretched_force(law, force_law, length);
      const StretchedForce iterative =
          solve_mount_stretch(at_length, length, law.mount_stiffness, StretchMode::kSelfConsistent);
      EXPECT_NEAR(s.force, iterative.force, 1e-9 * (1.0 + s.force)) << pressure << " " << length;
      EXPECT_NEAR(s.mount_stretch, total_mount_stretch(s.force, law.mount_stiffness), 1e-12);
    }
  }
  law.mount_stiffness.exponent = 2.0;
  law.mount_stiffness.preload = 0.0;
  EXPECT_GT(stretch_constants(law).inverse_compliance, 0.0);
}

TEST(MuscleLaw, ValidationNamesTheRestLengthAndTheStiffness) {
  MuscleLaw law{.fpam = paper::design_fpam(), .rest_length = 12.0};
  EXPECT_THROW(validate(law), InvalidParameter);
  law.rest_length = 0.3;
  EXPECT_NO_THROW(validate(law));
  law.stretch_mode = StretchMode::kOneShot;  // stiffness 0: no solution of F = K dx^2
  try {
    validate(law);
    ADD_FAILURE() << "no error";
  } catch (const InvalidParameter& e) {
    EXPECT_NE(std::string(e.what()).find("K1"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace softwrist::physics
