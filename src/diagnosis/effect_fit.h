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

EffectFit fit_effect(const GapProblem& problem, EffectId id, const BaseModel& base,
                     const sim::DeviceDescription& nominal, const DiagnosisOptions& options, std::uint64_t seed);

}  // namespace softwrist::diagnosis
