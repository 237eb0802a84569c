// A second effect beside a leader the verdict names on its own (issue 20: the verdict names the larger of two effects
// and reports the second). The second is reported where it acts where the leader cannot: on a gap trial the leader
// leaves untouched, it closes at least DiagnosisOptions::contradiction_gap noise units (docs/diagnosis.md, "A second
// effect beside a leader named on its own").
#pragma once

#include <cstddef>
#include <functional>
#include <vector>

#include "diagnosis/diagnosis.h"
#include "diagnosis/effect_fit.h"
#include "diagnosis/gap_problem.h"

namespace softwrist::diagnosis {

// Each trial's held-out systematic residual in `sums` (noise units; 0 for a trial without held-out points; empty where
// `sums` does not hold every trial of `problem`).
std::vector<double> heldout_excess_by_trial(const GapProblem& problem, const UnitSums& sums);

// The gap trials the combination's leader leaves untouched with room for a second effect: its held-out residual with
// the leader within DiagnosisOptions::second_untouched_fraction of what the leader's base left, and at least
// contradiction_gap noise units. All false where the residuals per trial were not recorded.
std::vector<bool> trials_the_leader_left(const Diagnosis& d, const DiagnosisOptions& options);

// The base a second effect `id` is fitted on: the leader's model, with `id`'s own tolerance parameters back at the
// nominal where the leader was fitted within the tolerances (so that the second takes its whole value). Called for one
// effect at a time.
using SecondBase = std::function<ModelVariant(EffectId)>;

// Where the leader leaves a gap trial untouched (trials_the_leader_left): every other applicable effect that acts on
// such a trial, fitted on top of the leader alone, with its held-out residual per trial recorded. The greedy
// combination tries only the effects that cut the whole held-out error most, and those mostly mop up the leader's
// misfit in the trials it moved (no catalogue form is the device's); a second acting elsewhere, on a trial of smaller
// weight, is not among them (the independent device's seed 39, strap_linear_preload + slow_vent: the regulator left the
// torque sweep at 3.30 noise units, and the mounts were no candidate). Empty where no trial is left.
std::vector<EffectFit> fit_seconds_where_untouched(const Diagnosis& d, const GapProblem& problem,
                                                   const SecondBase& base_of, const sim::DeviceDescription& nominal,
                                                   const DiagnosisOptions& options);

// Reports in d.also_effects, and in the reason, the second effect that acts where the leader cannot: of the
// combination's second member and the effects fitted on the trials the leader left (Diagnosis::seconds_where_untouched),
// the one that closes most of such a trial, at least contradiction_gap noise units. Nothing where none does.
void report_second_effect(Diagnosis& d, const DiagnosisOptions& options);

}  // namespace softwrist::diagnosis
