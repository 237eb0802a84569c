// diagnosis.html says the result first, and every sentence agrees with the numbers in the tables below it: a
// correction that closes the gap trials' gap while another trial still differs names that trial and its size.

#include "diagnosis/diagnosis_report.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "io/text_file.h"
#include "support/scratch_dir_test.h"

namespace softwrist::diagnosis {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;
using DiagnosisReportTest = softwrist::testing::ScratchDirTest;

TrialGap trial(const std::string& name, TrialKind kind, const std::string& unit, bool gap, bool remains,
               double rms_corrected, double excess_corrected) {
  TrialGap t;
  t.experiment = name;
  t.kind = kind;
  t.unit = unit;
  t.noise = 0.05;
  t.gap = gap;
  t.significant = gap;
  t.remaining_significant = remains;
  t.rms_corrected = rms_corrected;
  t.excess_corrected = excess_corrected;
  return t;
}

TEST_F(DiagnosisReportTest, SummaryNamesTheTrialThatKeepsASignificantGapAndItsSize) {
  Diagnosis d;
  d.verdict = "mount_stretch";
  d.reason = "mount_stretch explains 100 % of the held-out gap";
  d.heldout_nominal = 11.5;
  d.heldout_corrected = 0.8;
  d.gap_nominal = 22.2;
  d.gap_corrected = 0.0;
  d.remaining_gap_significant = true;
  d.trials = {trial("torque_sweep/trials", TrialKind::kTorqueSweep, "N m", true, false, 0.021, 0.0),
              trial("trajectory/trials:case 0", TrialKind::kTrajectory, "deg", false, true, 0.412, 1.73)};
  const DiagnosisReport report = write_diagnosis_report(d, dir_ / "out", {.plots = false});
  const std::string html = io::read_text_file(report.page);
  EXPECT_THAT(html, HasSubstr("<section class=\"summary attention\">"));
  EXPECT_THAT(html, HasSubstr("<b>Verdict: mount_stretch</b>."));
  EXPECT_THAT(html, HasSubstr("over the 1 trials with a gap of their own, 22.200 and 0.000: the correction closes "
                              "100 % of it."));
  EXPECT_THAT(html, HasSubstr("A significant gap remains after correction in 1 of 2 trials: trajectory/trials:case 0 "
                              "(RMS residual 0.412 deg, 1.73 noise units beyond its noise of 0.05 deg; it had no gap "
                              "of its own)."));
  EXPECT_THAT(html, HasSubstr("<tr class=\"significant\"><td>trajectory/trials:case 0</td>"));
  EXPECT_TRUE(std::filesystem::is_regular_file(dir_ / "out" / "style.css"));

  for (TrialGap& t : d.trials) t.remaining_significant = false;
  d.remaining_gap_significant = false;
  const std::string clean = io::read_text_file(write_diagnosis_report(d, dir_ / "clean", {.plots = false}).page);
  EXPECT_THAT(clean, HasSubstr("<section class=\"summary\">"));
  EXPECT_THAT(clean, HasSubstr("With the corrected model no trial differs from the simulation beyond its noise."));
  EXPECT_THAT(clean, Not(HasSubstr("remains after correction in")));
  // No trial with a gap of its own: no share closed is claimed.
  for (TrialGap& t : d.trials) t.gap = false;
  const std::string no_gap = io::read_text_file(write_diagnosis_report(d, dir_ / "no_gap", {.plots = false}).page);
  EXPECT_THAT(no_gap, HasSubstr("over all 2 trials; no trial keeps a gap of its own, so the correction has none to "
                                "close."));
  EXPECT_THAT(no_gap, Not(HasSubstr("the correction closes")));
}

}  // namespace
}  // namespace softwrist::diagnosis
