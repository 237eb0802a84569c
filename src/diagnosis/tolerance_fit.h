#pragma once
// The nominal within its tolerances (tolerance.h), fitted to the training part of the data: the catalogue's
// parameters that the tolerances free (one r0 scale, one wrist radius scale, ...), and what differs from one muscle,
// rig or regulator to the next (each muscle's hand anchor and rest length, each rig's joint limits towards the
// passive range, each pressure monitor's offset and gain), all at once by bounded least squares
// (optimize/bounded_least_squares.h) from the nominal as placed. Internal to src/diagnosis.

#include "diagnosis/diagnosis.h"
#include "diagnosis/gap_problem.h"

namespace softwrist::diagnosis {

ToleranceFit fit_within_tolerances(const GapProblem& problem, const ModelVariant& nominal,
                                   const DiagnosisOptions& options);

}  // namespace softwrist::diagnosis
