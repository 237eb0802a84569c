#pragma once
// The greedy combination fits each effect on top of those before it, so an effect that joined early keeps values
// chosen while a later one was missing (a soft mount standing in for a stiff wrist until the wrist joins). Where the
// values matter, not only which effects there are (a calibration), all the combination's parameters are refitted
// together from there. Internal to src/diagnosis.

#include <span>
#include <vector>

#include "diagnosis/diagnosis.h"
#include "diagnosis/gap_problem.h"

namespace softwrist::diagnosis {

// The nominal (as placed, with the rigs its trials name) with the combination's effects applied in the order they
// joined, each with `values[e]`.
ModelVariant combined_variant(const std::vector<EffectFit>& combination, const std::vector<std::vector<double>>& values,
                              const ModelVariant& nominal);

// Refits every parameter of `combination` at once on the training part (Levenberg-Marquardt within the catalogue's
// ranges, in the space the fits search), updating its values and named parameters. Returns the refitted model.
ModelVariant refit_jointly(const GapProblem& problem, std::vector<EffectFit>& combination, const ModelVariant& nominal,
                           const DiagnosisOptions& options);

}  // namespace softwrist::diagnosis
