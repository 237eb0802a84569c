#pragma once
// How a measurement was taken, as its user states it at import (docs/diagnosis.md, "Conventions"): what a torque
// sweep's reading includes, the arm's posture (which wrist axis the hand's weight acts on), whether the angles were
// zeroed at the start of the trial, the angle sensor's resolution, and which rig (placement file) it came from. The
// replay honours each, so that a convention of the rig is not mistaken for an unmodelled effect.

#include <filesystem>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "physics/exosuit_layout.h"

namespace softwrist::diagnosis {

enum class Posture {
  kHandSupported,  // a table carries the hand: no weight on either axis
  kGravityFe,      // forearm horizontal and pronated (palm down): the hand's weight flexes the wrist
  kGravityUr,      // forearm horizontal in mid-pronation (thumb up): the weight deviates ulnarly (the model's frame)
};
const char* to_string(Posture posture);
std::optional<Posture> posture_from_name(const std::string& name);
// The axis the hand's weight turns, or nothing when the hand is supported.
std::optional<physics::WristAxis> gravity_axis(Posture posture);

// What a torque sweep's sensor reads besides the muscle's own torque. A sensor on the hand plate weighs the relaxed
// wrist's torque at the held angle, and, with the plate vertical, the hand's weight; "baseline_subtracted" is the
// reading less the same angle's reading at 0 kPa, which removes both and the deflated muscle's own pull.
struct TorqueIncludes {
  bool passive_wrist = false;
  bool hand_weight = false;
  bool baseline_subtracted = false;
  // The reading moves with the relaxed wrist's torque (a baseline subtraction removes it whatever else is named).
  bool weighs_passive_wrist() const { return passive_wrist && !baseline_subtracted; }
  bool operator==(const TorqueIncludes&) const = default;
};
// "muscle", "muscle+passive_wrist", "muscle+hand_weight", "muscle+passive_wrist+hand_weight" (the terms in any
// order) or "baseline_subtracted".
std::optional<TorqueIncludes> torque_includes_from_name(const std::string& name);
std::string to_string(const TorqueIncludes& includes);

struct Conventions {
  // Unstated: the model's own frame (gravity on ulnar/radial deviation), as softwrist's simulated runs are.
  Posture posture = Posture::kGravityUr;
  TorqueIncludes torque;
  // The angles read 0 at the trial's start (IMUs or markers zeroed on the relaxed wrist): the replay's angles are
  // read relative to its own at that instant.
  bool angles_zeroed_at_start = false;
  double angle_resolution = 0.0;  // [rad] the angle sensor's step (a BNO055 reports 1/16 deg); 0: finer than the noise
  // The rig's placement file (absolute); empty: the model the diagnosis is given (`diagnose --model`).
  std::filesystem::path placement;
};

// The conventions a log's config states. Keys: "posture", "hand_supported" (true: posture hand_supported; written
// by the tracking experiments), "torque_includes", "angles_zeroed_at_start", "angle_resolution_deg", "placement" (a
// path, relative to `log_dir`). Throws std::runtime_error naming `source` and the field of an unknown value.
Conventions conventions_from_config(const nlohmann::json& config, const std::filesystem::path& log_dir,
                                    const std::string& source);
// Writes what differs from the defaults into `config` (the placement as given).
void write_conventions(const Conventions& conventions, nlohmann::json& config);

}  // namespace softwrist::diagnosis
