#pragma once
// The nominal within its tolerances (tolerance.h), fitted to the training part of the data: the catalogue's
// parameters that the tolerances free (one r0 scale, one wrist radius scale, ...), and what differs from one muscle,
// rig or regulator to the next (each muscle's hand anchor and rest length, each rig's joint limits towards the
// passive range, each pressure monitor's offset and gain), all at once by bounded least squares
// (optimize/bounded_least_squares.h) from the nominal as placed. Internal to src/diagnosis.

#include <span>
#include <vector>

#include "diagnosis/diagnosis.h"
#include "diagnosis/gap_problem.h"

namespace softwrist::diagnosis {

ToleranceFit fit_within_tolerances(const GapProblem& problem, const ModelVariant& nominal,
                                   const DiagnosisOptions& options);

// The nominal within its tolerances where their fit `within` ended (or at `tolerances`, the values of its free
// parameters in its order, where given), with the own tolerance parameters of the effects `ids` back at the nominal:
// the base an effect is fitted on beyond the tolerances (it then takes its whole value).
ModelVariant within_tolerances_without(const GapProblem& problem, const ModelVariant& nominal,
                                       const DiagnosisOptions& options, const ToleranceFit& within,
                                       std::span<const EffectId> ids, std::span<const double> tolerances = {});

// Effect `id` on top of the nominal within its tolerances, fitted jointly with them by the same least squares, from
// where the tolerance fit `within` ended with the effect at `start`, or, where given and its training error is lower,
// from the nominal with the effect at `start_from_nominal` (its fit from the nominal as placed: where the effect is
// large, the tolerance fit ends distorted at the edges of its boxes, far from the joint optimum). Where neither start
// can be built or replayed, the effect at its neutral value (fit_start) on the tolerances as fitted, then on the
// nominal. The effect's own tolerance parameters stay at the nominal: it takes its whole value, and its values are not
// shared with a tolerance that says the same. What an effect closes beyond the tolerances
// (Diagnosis::beyond_tolerance).
struct JointFit {
  ModelVariant variant;
  std::vector<double> values;      // the effect's, in its spec's units
  std::vector<double> tolerances;  // the free parameters of the tolerance fit, in its order
  int evaluations = 0;
};
JointFit fit_effect_within_tolerances(const GapProblem& problem, const ModelVariant& nominal,
                                      const DiagnosisOptions& options, const ToleranceFit& within, EffectId id,
                                      std::span<const double> start, std::span<const double> start_from_nominal = {});

}  // namespace softwrist::diagnosis
