#pragma once
// End-to-end diagnoses: each synthesizes a data set and diagnoses it with every effect and the tolerance fit, 15 s to
// 2 min in the normal build and five to eight times that under AddressSanitizer, where together they made the
// sanitizer stage of CI over half an hour. The sanitizer build skips them (reported as skipped, with this reason);
// scripts/test.sh runs them in the normal build, and CI runs both. The diagnosis's code stays under the sanitizers
// through its shorter tests (NoEffectGivesNone, MeasuredPressuresTellRegulatorDeadTimeFromImuLatency, the CLI's
// synthesize-import-diagnose-report test, the localisation, tolerance and conventions tests).
// SOFTWRIST_SKIP_UNDER_SANITIZERS(why) skips another test whose code the sanitizers see through shorter ones.

#include <gtest/gtest.h>

// GCC says so with __SANITIZE_ADDRESS__, clang (the sanitizer build's compiler in CI) with __has_feature.
#if defined(__has_feature)
#if __has_feature(address_sanitizer)
#define SOFTWRIST_UNDER_ADDRESS_SANITIZER 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__) || defined(SOFTWRIST_UNDER_ADDRESS_SANITIZER)
#define SOFTWRIST_SKIP_UNDER_SANITIZERS(why) GTEST_SKIP() << why << ": run in the normal build (bash scripts/test.sh)"
#else
#define SOFTWRIST_SKIP_UNDER_SANITIZERS(why) static_cast<void>(0)
#endif
#define SOFTWRIST_SKIP_END_TO_END_UNDER_SANITIZERS() SOFTWRIST_SKIP_UNDER_SANITIZERS("an end-to-end diagnosis")
