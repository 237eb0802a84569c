#pragma once
// Personalisation (Fig. Personalization_pipeline): from a user's arm dimensions, their reference torque profiles
// and the pressure limit, the placement of all four fPAMs (Section Parameter optimization, for each muscle in its
// own plane), ready to be written as a placement file and a MuJoCo model.
//
// The bounds follow Section Parameter optimization's reasoning for Table optimized_parameters: d1 and d2 between a
// minimum distance from the wrist (room to place a short fPAM across it) and how far the forearm and hand reach;
// w1 and w2 from the skin (half the limb's thickness for flexor and extensor, half its width for the ulnar and
// radial muscles) up to the height of an elevating mount (Fig. EndpointAttachment(c)). The user file format is in
// docs/personalize.md.

#include <array>
#include <filesystem>
#include <string>

#include "io/json_reader.h"
#include "optimize/design_optimizer.h"
#include "physics/exosuit_layout.h"

namespace softwrist::optimize {

struct UserDescription {
  std::string name;
  double pressure_limit = physics::kRegulatorMaxPressure;  // [Pa]
  physics::FpamParameters fpam = physics::FpamParameters::Constant(0.0123, 0.28);
  double wrist_radius_fe = 0.02;  // [m] half the wrist's palmar-dorsal thickness
  double wrist_radius_ur = 0.02;  // [m] half the wrist's radial-ulnar width
  // Range of motion [rad, positive]: flexion, extension, ulnar, radial (the order of sim::MuscleIndex's directions).
  std::array<double, 4> range{};
  std::array<PlacementBounds, 4> bounds{};                      // flexor, extensor, ulnar, radial
  std::array<ReferenceTorque, 4> references{};                  // resampled, angles in each muscle's own direction
  physics::Placement start_resolution = kPaperStartResolution;  // [m] of the multi-start grid
};

// A constant-parameter design fPAM from a config object's "fpam" {"r0_cm", "eps_max"} (defaults: Section Parameter
// optimization's 1.23 cm and 0.28), errors naming the field.
physics::FpamParameters read_design_fpam(io::JsonReader reader);

// Reads a user file (format "softwrist.user/1"); errors name the file and the field, or the CSV's line and column.
UserDescription load_user(const std::filesystem::path& path, int samples = 140);

struct PersonalizedMuscle {
  physics::Muscle muscle;    // placement, L0, r_w, fPAM
  double objective = 0.0;    // [N m], Eqn. objective_function at the optimum
  double max_deficit = 0.0;  // [N m], <= 0 where it meets the reference everywhere
  long evaluations = 0;
};

// The design problem of one muscle (0 flexor, 1 extensor, 2 ulnar, 3 radial): L0 from Eqn. length at the end of
// the range that stretches it (extension for the flexor, flexion for the extensor, radial for the ulnar muscle,
// ulnar for the radial).
DesignProblem user_design_problem(const UserDescription& user, int muscle);

// Runs the four optimizations; options.start_resolution is taken from the user description.
std::array<PersonalizedMuscle, 4> personalize(const UserDescription& user, OptimizerOptions options);

}  // namespace softwrist::optimize
