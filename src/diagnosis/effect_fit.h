#pragma once
// One effect of the catalogue fitted on top of a base model (the nominal one, or the combination so far): its
// parameters searched on the training part of the data, then measured on the held-out part with a bootstrap
// interval (diagnosis.h). Internal to src/diagnosis.

#include <cstdint>

#include "diagnosis/diagnosis.h"
#include "diagnosis/gap_problem.h"

namespace softwrist::diagnosis {

// The base model an effect is added to, with its predictions on the training part and on all the data.
struct BaseModel {
  const ModelVariant& variant;
  const Predictions& training;
  const Predictions& full;
};

// The effects the options ask for: their list, or the whole catalogue when it is empty.
std::vector<EffectId> requested_effects(const DiagnosisOptions& options);

// Which trials have a gap and are of a kind `spec` acts on (a trial is the index into `trials`).
std::vector<bool> gap_trials_acted_on(const std::vector<TrialGap>& trials, const EffectSpec& spec);

EffectFit fit_effect(const GapProblem& problem, EffectId id, const BaseModel& base,
                     const sim::DeviceDescription& nominal, const DiagnosisOptions& options, std::uint64_t seed);

}  // namespace softwrist::diagnosis
