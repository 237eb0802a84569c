#pragma once
// What each catalogue effect explains beyond the nominal's tolerances (docs/diagnosis.md, "Ranked beyond the
// tolerances"; experimental, DiagnosisOptions::rank_beyond_tolerances). A real device differs from its placement file
// within its tolerances and has an effect besides; fitted from the file as placed, every effect competes with that
// scatter, and the one that soaks up most of it (often the fPAM's parameters or the mounts) leads whatever the effect
// is. Here each effect is fitted on top of the nominal within its tolerances, so that it is judged on the gap the
// tolerances leave. Selection and report use different parts of the data: the effects are ranked by the training error
// they leave, and what the leader closes is measured on the held-out part. Internal to src/diagnosis.

#include <cstdint>
#include <optional>
#include <vector>

#include "diagnosis/diagnosis.h"
#include "diagnosis/effect_fit.h"
#include "diagnosis/gap_problem.h"

namespace softwrist::diagnosis {

// Each applicable effect fitted on the nominal within its tolerances (its own tolerance parameters released into its
// whole range, the others held where their fit `within` ended), then the best `options.beyond_joint_candidates` of
// them refitted jointly with every tolerance (kept where that lowers their training error; only the leader when it
// already closes 90 % of the held-out gap beyond the tolerances). Best first by training error. The problem's scored
// trials are those with a gap beyond the tolerances; `trials` says which they are.
// `as_placed` is the nominal as placed with its predictions.
std::vector<Diagnosis::BeyondTolerance> rank_beyond_tolerances(const GapProblem& problem, const BaseModel& as_placed,
                                                               const sim::DeviceDescription& nominal_device,
                                                               const ToleranceFit& within,
                                                               const std::vector<TrialGap>& trials,
                                                               const DiagnosisOptions& options);

// A second effect on top of the leader's model (the tolerances held where the leader's fit left them, the second's
// own back at the nominal): of the other effects in `ranked` that close
// min_gain of the held-out gap on their own, the two that close most are fitted on it, and the better by training
// error is kept; scored against the nominal within its tolerances (its explained_fraction is the pair's), its
// bootstrap interval that of the cut it makes in what the leader leaves. None when no other effect qualifies.
std::optional<Diagnosis::BeyondTolerance> second_beyond_tolerances(
    const GapProblem& problem, const ModelVariant& nominal, const sim::DeviceDescription& nominal_device,
    const ToleranceFit& within, const std::vector<TrialGap>& trials,
    const std::vector<Diagnosis::BeyondTolerance>& ranked, const DiagnosisOptions& options);

}  // namespace softwrist::diagnosis
