#pragma once
// One effect of the catalogue fitted on top of a base model (the nominal one, or the combination so far): its
// parameters searched on the training part of the data, then measured on the held-out part with a bootstrap
// interval (diagnosis.h). Internal to src/diagnosis.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

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

// Which trials have a gap (TrialGap::gap; with as_placed, TrialGap::gap_as_placed) and are changed by `spec`
// (acts_on in replay.h; `trials` in the order of problem's).
std::vector<bool> gap_trials_acted_on(const GapProblem& problem, const std::vector<TrialGap>& trials,
                                      const EffectSpec& spec, bool as_placed = false);

// The leader of a round of fits on one base model (an index into `fits`; fits.size() when none is applicable): with
// `one_se_rule`, of the applicable fits whose held-out error the data do not tell from the lowest one's (within one
// bootstrap standard error of the paired difference: the one-standard-error rule of Breiman, Friedman, Olshen & Stone
// 1984, Sec. 3.4.3, and Hastie, Tibshirani & Friedman 2009, Sec. 7.10), the one with the fewest parameters (those
// fitted into its base included, EffectFit::base_parameters), then the lowest error; otherwise the lowest error. The
// held-out error already charges an effect for fitting noise; the rule adds parsimony only among what the data cannot
// separate. Among those, the training part, which the fits were made on and which holds as many units, breaks the
// tie where it tells them apart: the one with the lowest training gap leads instead where the fewest-parameter one's
// lies more than DiagnosisOptions::training_separation_se paired bootstrap standard errors above it. A fit that barely
// moves the part it was fitted on and gains on the held-out one compensates for something else. Records each fit's
// standard error and whether it is within one.
// Only fits that `eligible` accepts compete (all applicable ones when it is empty).
std::size_t leader_of_round(const GapProblem& problem, std::vector<EffectFit>& fits, const DiagnosisOptions& options,
                            std::uint64_t seed, const std::function<bool(const EffectFit&)>& eligible = {});

// Whether a single fit may join the greedy combination: it cuts the held-out error of its base by min_gain, its
// bootstrap interval above zero where the interval is informative (enough held-out units).
bool joins_combination(const EffectFit& fit, bool interval_informative, const DiagnosisOptions& options);

// The leader of the single fits (leader_of_round) among those that may join the combination, which starts from it on
// the base it was fitted on; among all applicable ones where none may. A leader that did not help (a relaxed wrist
// within one standard error of the best, cutting nothing) put its base under the first that did: on the independent
// device's aged fabric an fPAM fitted from the tolerances with its own r0 at the nominal went on top of a base with r0
// already at its tolerance's edge, and "explained -342 %" of the gap.
std::size_t leader_of_single_fits(const GapProblem& problem, std::vector<EffectFit>& fits,
                                  const DiagnosisOptions& options, std::uint64_t seed, bool interval_informative);

// Where the search of effect `id` on `base` ended (fit_effect's first part) and the held-out sums there. It reads no
// scoring (GapProblem::set_scored), so it may run while the scored trials are still being decided.
struct EffectSearch {
  bool applicable = false;
  std::vector<double> u;  // in the unit cube of the effect's parameters
  double training_error = 0.0;
  UnitSums heldout_after, training_after;
  int evaluations = 0;
};
EffectSearch search_effect(const GapProblem& problem, EffectId id, const BaseModel& base,
                           const DiagnosisOptions& options);

// Effect `id` fitted on `base`'s training part and scored on its held-out part, in its base form: its parameters
// searched (the start, a coarse grid, Levenberg-Marquardt on the training residuals), its extensions
// (ParameterSpec::extension) held at their starting values. `searched`: search_effect's result for the same
// effect and base, where it has been run already.
EffectFit fit_effect(const GapProblem& problem, EffectId id, const BaseModel& base,
                     const sim::DeviceDescription& nominal, const DiagnosisOptions& options, std::uint64_t seed,
                     const EffectSearch* searched = nullptr);

// The extensions of an applicable base-form `fit` on the same `base`, whatever its base form closed (an extension can
// change the form's shape where the base form has nothing to move: a relaxed wrist much softer towards flexion than
// towards extension is not fitted by one scale; the gate of commit 1e77e5d, the base form closing min_gain of the
// held-out gap or of the training error, left the independent benchmark's direction_dependent at level 0.8
// `unexplained`, docs/diagnosis.md): every parameter searched again, from the base form's optimum and from the start,
// each with the extensions at 0.2, 0.5 and 0.8 of their ranges (a base form that has taken part of an extension's
// effect can sit far from the joint optimum), then Levenberg-Marquardt from the best (ranked on coarse replays, the
// first confirmed on fine ones: Fidelity). Kept, and `fit` updated with `extended` set, only where they lower the
// held-out error by more than one paired bootstrap standard error (the one-standard-error rule of the ranking, within
// an effect: a dead time the data pin down is not traded for a second-order regulator they cannot tell from it).
// Returns whether they were kept.
bool extend_fit(const GapProblem& problem, EffectFit& fit, const BaseModel& base, const sim::DeviceDescription& nominal,
                const DiagnosisOptions& options, std::uint64_t seed);

}  // namespace softwrist::diagnosis
