#include "optimize/personalize.h"

#include <fmt/format.h>

#include "io/json_reader.h"
#include "io/text_file.h"
#include "physics/errors.h"
#include "physics/exosuit_layout.h"
#include "physics/units.h"

namespace softwrist::optimize {
namespace {

using units::cm_to_m;
using units::deg_to_rad;

constexpr const char* kUserFormat = "softwrist.user/1";
constexpr std::array<const char*, 4> kMuscles = {"flexor", "extensor", "ulnar", "radial"};
constexpr std::array<const char*, 4> kDirections = {"flexion", "extension", "ulnar", "radial"};
// The direction whose end stretches each muscle: extension for the flexor, and so on.
constexpr std::array<int, 4> kStretchedBy = {1, 0, 3, 2};

struct Limb {
  double min_distance = 0.0, max_distance = 0.0;  // d range [m]
  double thickness = 0.0, width = 0.0;            // [m]
  double elevation = 0.0;                         // [m] of an elevating mount
};

Limb read_limb(io::JsonReader reader) {
  Limb limb{.min_distance = cm_to_m(reader.positive("min_mount_distance_cm")),
            .max_distance = cm_to_m(reader.positive("max_mount_distance_cm")),
            .thickness = cm_to_m(reader.positive("thickness_cm")),
            .width = cm_to_m(reader.positive("width_cm")),
            .elevation = cm_to_m(reader.non_negative("max_elevation_cm", 0.0))};
  if (limb.max_distance < limb.min_distance) reader.fail("max_mount_distance_cm", "must be >= min_mount_distance_cm");
  reader.finish();
  return limb;
}

}  // namespace

physics::FpamParameters read_design_fpam(io::JsonReader reader) {
  const double r0 = cm_to_m(reader.positive("r0_cm", 1.23));
  const double eps_max = reader.positive("eps_max", 0.28);
  reader.finish();
  try {
    return physics::FpamParameters::Constant(r0, eps_max);
  } catch (const std::exception& e) {
    reader.fail("", e.what());
  }
}

UserDescription load_user(const std::filesystem::path& path, int samples) {
  const std::string source = path.string();
  const nlohmann::json root = io::parse_json(io::read_text_file(path), source);
  io::JsonReader top(root, source, "");
  if (const std::string format = top.text("format"); format != kUserFormat) {
    top.fail("format", fmt::format("'{}' is not '{}'", format, kUserFormat));
  }
  UserDescription user;
  user.name = top.text("name", path.stem().string());
  user.pressure_limit = units::kpa_to_pa(top.positive("pressure_limit_kpa", physics::kRegulatorMaxPressureKpa));
  if (top.has("fpam")) user.fpam = read_design_fpam(top.child("fpam"));
  io::JsonReader wrist = top.child("wrist");
  user.wrist_radius_fe = cm_to_m(wrist.positive("radius_fe_cm", 2.0));
  user.wrist_radius_ur = cm_to_m(wrist.positive("radius_ur_cm", 2.0));
  io::JsonReader range = wrist.child("range_deg");
  for (std::size_t i = 0; i < 4; ++i) {
    const double degrees = range.positive(kDirections[i]);
    if (degrees >= 120.0) range.fail(kDirections[i], "must be below 120");
    user.range[i] = deg_to_rad(degrees);
  }
  range.finish();
  wrist.finish();
  const Limb forearm = read_limb(top.child("forearm"));
  const Limb hand = read_limb(top.child("hand"));
  for (std::size_t i = 0; i < 4; ++i) {
    const bool fe = i < 2;
    const double w1 = 0.5 * (fe ? forearm.thickness : forearm.width);
    const double w2 = 0.5 * (fe ? hand.thickness : hand.width);
    user.bounds[i] = {.lower = {.d1 = forearm.min_distance, .w1 = w1, .d2 = hand.min_distance, .w2 = w2},
                      .upper = {.d1 = forearm.max_distance,
                                .w1 = w1 + forearm.elevation,
                                .d2 = hand.max_distance,
                                .w2 = w2 + hand.elevation}};
  }
  if (top.has("start_resolution_cm")) {
    io::JsonReader r = top.child("start_resolution_cm");
    user.start_resolution = {.d1 = cm_to_m(r.positive("d1")),
                             .w1 = cm_to_m(r.positive("w1")),
                             .d2 = cm_to_m(r.positive("d2")),
                             .w2 = cm_to_m(r.positive("w2"))};
    r.finish();
  }
  io::JsonReader references = top.child("references");
  for (std::size_t i = 0; i < 4; ++i) {
    const std::filesystem::path file = references.text(kMuscles[i]);
    const auto resolved = file.is_absolute() ? file : std::filesystem::absolute(path).parent_path() / file;
    if (!std::filesystem::is_regular_file(resolved)) references.fail(kMuscles[i], "no such file: " + resolved.string());
    user.references[i] = resample(read_reference_torque(resolved), samples);
  }
  references.finish();
  top.finish();
  for (int i = 0; i < 4; ++i) {
    try {
      validate(user_design_problem(user, i));
    } catch (const physics::InvalidParameter& e) {
      top.fail(kMuscles[static_cast<std::size_t>(i)], fmt::format("the bounds this file gives: {}", e.what()));
    }
  }
  return user;
}

DesignProblem user_design_problem(const UserDescription& user, int muscle) {
  const auto i = static_cast<std::size_t>(muscle);
  DesignProblem problem;
  problem.samples = user.references[i];
  problem.fpam = user.fpam;
  problem.pressure = user.pressure_limit;
  problem.wrist_radius = i < 2 ? user.wrist_radius_fe : user.wrist_radius_ur;
  problem.max_stretch_angle = -user.range[static_cast<std::size_t>(kStretchedBy[i])];
  problem.bounds = user.bounds[i];
  return problem;
}

std::array<PersonalizedMuscle, 4> personalize(const UserDescription& user, OptimizerOptions options) {
  options.start_resolution = user.start_resolution;
  const auto one = [&](int i) {
    const DesignProblem problem = user_design_problem(user, i);
    const DesignResult design = optimize_design(problem, options);
    const DesignEvaluator evaluator(problem);
    return PersonalizedMuscle{.muscle = design_muscle(problem, design.best.placement),
                              .objective = design.best.objective,
                              .max_deficit = evaluator.max_deficit(design.best.placement),
                              .evaluations = design.evaluations};
  };
  return {one(0), one(1), one(2), one(3)};
}

}  // namespace softwrist::optimize
