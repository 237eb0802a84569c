// `softwrist report`'s page (report/html_report.h) on a real run: metrics beside the paper's, plots written by
// matplotlib and linked from the page, provenance, and clear errors for what is not a run directory.

#include "report/html_report.h"

#include <fstream>

#include <nlohmann/json.hpp>

#include <fmt/format.h>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "experiments/runner.h"
#include "io/subprocess.h"
#include "io/text_file.h"
#include "report/page_style.h"
#include "support/scratch_dir_test.h"

namespace softwrist::report {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
const fs::path kSource = SOFTWRIST_SOURCE_DIR;

class HtmlReportTest : public testing::ScratchDirTest {
 protected:
  // A quick range-of-motion run (one repetition) in the scratch directory.
  fs::path rom_run() {
    std::ofstream(dir_ / "rom.json") << R"({"format": "softwrist.experiment/1", "kind": "range_of_motion", "model": ")"
                                     << (kSource / "models/rom_device.json").string()
                                     << R"(", "repetitions": 1, "description": "RoM <quick> & small"})";
    experiments::run_experiment(experiments::load_experiment_config(dir_ / "rom.json"),
                                {.out = dir_ / "run", .jobs = 2});
    return dir_ / "run";
  }
};

// The page holds the paper's Table RoM values beside the simulated ones, the escaped description, the run's
// hashes, and an <img> for each plot, which is a PNG on disk.
TEST_F(HtmlReportTest, RangeOfMotionPageHasMetricsPlotsAndProvenance) {
  const fs::path run = rom_run();
  const ReportResult result = write_report(run);
  EXPECT_EQ(result.page, run / "report" / "index.html");
  const std::string html = io::read_text_file(result.page);
  EXPECT_THAT(html, HasSubstr("RoM &lt;quick&gt; &amp; small"));
  EXPECT_THAT(html, HasSubstr("<td>flexion range [deg]</td>"));
  // Table RoM, the paper's exosuit flexion, in the paper's (highlighted) column and in the summary box's sentence.
  EXPECT_THAT(html, HasSubstr("<td class=\"num paper\">44.5 ± 7.5 (biological 80.9)</td>"));
  EXPECT_THAT(html, HasSubstr("<section class=\"summary\">\n<p><b>extension range [deg]</b>: "));
  EXPECT_THAT(html, HasSubstr("; 44.5 ± 7.5 (biological 80.9) in the paper"));
  EXPECT_THAT(html, HasSubstr("<link rel=\"stylesheet\" href=\"style.css\">"));
  EXPECT_THAT(io::read_text_file(run / "report" / "style.css"), HasSubstr(".summary"));
  EXPECT_THAT(html, HasSubstr("fnv1a64:"));
  ASSERT_EQ(result.plots.size(), 1u);
  for (const std::string& plot : result.plots) {
    EXPECT_THAT(html, HasSubstr("<img src=\"" + plot + "\""));
    EXPECT_EQ(io::read_text_file(run / "report" / plot).substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8)) << plot;
  }
  // The renders: each muscle settled (first repetition), an <img> each.
  EXPECT_EQ(result.renders, (std::vector<std::string>{"render_rom_flexor.png", "render_rom_extensor.png",
                                                      "render_rom_ulnar.png", "render_rom_radial.png"}));
  for (const std::string& render : result.renders) EXPECT_THAT(html, HasSubstr("<img src=\"" + render + "\""));
  EXPECT_THAT(html, HasSubstr("The flexor alone at 137 kPa, settled"));
  const ReportResult bare = write_report(run, {.out = dir_ / "bare", .plots = false, .renders = false});
  EXPECT_TRUE(bare.plots.empty());
  EXPECT_TRUE(bare.renders.empty());
  EXPECT_THAT(io::read_text_file(bare.page), ::testing::Not(HasSubstr("<img")));
}

// The page in a real browser (Debian's chromium, headless; scripts/test.sh installs it), 1280 px wide: the page's own
// check counts the images that loaded into <body data-images> and lists any box whose text overflows it in
// data-overflow; every panel of every plot names both axes with a unit (plot_run.py's plots.json); a missing PNG is
// named on the page. The screenshot is kept as an artifact of the test run: build/.../test-artifacts/report_rom.png.
TEST_F(HtmlReportTest, OpensInHeadlessChromiumWithEveryImageLoadedAndNothingOverflowing) {
  if (!fs::exists("/usr/bin/chromium"))
    GTEST_SKIP() << "Debian's chromium is not installed (scripts/test.sh installs it)";
  const fs::path run = rom_run();
  const ReportResult report = write_report(run);
  const auto chromium = [&](const std::vector<std::string>& args, const fs::path& output) {
    std::vector<std::string> argv = {"/usr/bin/chromium",
                                     "--headless",
                                     "--no-sandbox",
                                     "--disable-gpu",
                                     "--window-size=1280,2400",
                                     "--user-data-dir=" + (dir_ / "chromium-profile").string()};
    argv.insert(argv.end(), args.begin(), args.end());
    argv.push_back("file://" + report.page.string());
    return io::run_process(argv, {.stdout_file = output, .stderr_file = dir_ / "chromium.log"});
  };
  const std::size_t images = report.plots.size() + report.renders.size();
  ASSERT_EQ(images, 5u);
  ASSERT_EQ(chromium({"--dump-dom", "--virtual-time-budget=10000"}, dir_ / "dom.html"), 0)
      << io::read_text_file(dir_ / "chromium.log");
  EXPECT_THAT(io::read_text_file(dir_ / "dom.html"),
              HasSubstr(fmt::format("<body data-images=\"{0}/{0}\" data-overflow=\"none\">", images)));
  const fs::path artifacts = fs::path(SOFTWRIST_TEST_ARTIFACT_DIR);
  fs::create_directories(artifacts);
  ASSERT_EQ(chromium({"--screenshot=" + (artifacts / "report_rom.png").string()}, dir_ / "out.txt"), 0);
  EXPECT_EQ(io::read_text_file(artifacts / "report_rom.png").substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));

  const nlohmann::json plots = nlohmann::json::parse(io::read_text_file(run / "report" / "plots.json"));
  for (const auto& plot : plots) {
    ASSERT_FALSE(plot["axes"].empty()) << plot.dump();
    for (const auto& axes : plot["axes"]) {  // a unit in brackets, but for an axis of categories (the muscles)
      const std::string with_unit = ".+\\[.+\\].*";
      EXPECT_THAT(axes["xlabel"].get<std::string>(),
                  ::testing::MatchesRegex(axes["x_categorical"].get<bool>() ? ".+" : with_unit))
          << plot.dump();
      EXPECT_THAT(axes["ylabel"].get<std::string>(), ::testing::MatchesRegex(with_unit)) << plot.dump();
    }
  }

  fs::remove(run / "report" / report.renders.front());
  ASSERT_EQ(chromium({"--dump-dom", "--virtual-time-budget=10000"}, dir_ / "dom.html"), 0);
  const std::string dom = io::read_text_file(dir_ / "dom.html");
  EXPECT_THAT(dom, HasSubstr(fmt::format("<body data-images=\"{}/{}\"", images - 1, images)));
  EXPECT_THAT(dom, HasSubstr("image missing: " + report.renders.front()));
}

// The overflow check can fail: a word too long for its box is named in data-overflow.
TEST_F(HtmlReportTest, HeadlessChromiumNamesTextThatOverflowsItsBox) {
  if (!fs::exists("/usr/bin/chromium"))
    GTEST_SKIP() << "Debian's chromium is not installed (scripts/test.sh installs it)";
  write_stylesheet(dir_);
  std::ofstream(dir_ / "page.html") << page_head("overflow", "")
                                    << "<div style=\"width: 200px; overflow-wrap: normal\">" << std::string(120, 'W')
                                    << "</div>\n"
                                    << page_end();
  ASSERT_EQ(io::run_process({"/usr/bin/chromium", "--headless", "--no-sandbox", "--disable-gpu",
                             "--window-size=1280,800", "--user-data-dir=" + (dir_ / "chromium-profile").string(),
                             "--dump-dom", "--virtual-time-budget=5000", "file://" + (dir_ / "page.html").string()},
                            {.stdout_file = dir_ / "dom.html", .stderr_file = dir_ / "chromium.log"}),
            0);
  EXPECT_THAT(io::read_text_file(dir_ / "dom.html"), HasSubstr("data-overflow=\"div 'WWWW"));
}

TEST_F(HtmlReportTest, NotARunDirectoryIsAClearError) {
  EXPECT_THAT([&] { write_report(dir_ / "nope"); },
              ::testing::ThrowsMessage<std::runtime_error>(HasSubstr("not a directory")));
  const fs::path run = rom_run();
  fs::remove(run / "summary.json");
  EXPECT_THAT([&] { write_report(run); }, ::testing::ThrowsMessage<std::runtime_error>(
                                              HasSubstr("summary.json: missing (is this a run directory?)")));
  std::ofstream(run / "summary.json") << "{ not json";
  EXPECT_THAT([&] { write_report(run); },
              ::testing::ThrowsMessage<std::runtime_error>(HasSubstr("summary.json: invalid JSON")));
}

// Tracking metrics: each controller's RMSE beside the paper's 5.18 / 7.12 deg.
TEST(MetricRows, TrackingRowsPutTheControllersBesideThePaper) {
  const nlohmann::json summary = {
      {"paper", {{"rmse_fe_deg", 5.18}, {"rmse_ur_deg", 7.12}}},
      {"controllers",
       {{{"controller", "paper"}, {"rmse_fe_deg", 6.39}, {"reachable_rmse_fe_deg", 5.79}, {"rmse_ur_deg", nullptr}}}}};
  const auto rows = metric_rows("tracking", summary);
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(rows[0][0], "paper: RMSE fe, all (reachable) targets [deg]");
  EXPECT_EQ(rows[0][1], "6.39 (5.79)");
  EXPECT_EQ(rows[0][2], "5.18");
  EXPECT_EQ(summary_lines("tracking", summary),
            std::vector<std::string>{"<b>paper: RMSE fe, all (reachable) targets [deg]</b>: 6.39 (5.79) here; 5.18 in "
                                     "the paper"});
  EXPECT_EQ(html_escape("<a href=\"x\">&</a>"), "&lt;a href=&quot;x&quot;&gt;&amp;&lt;/a&gt;");
}

}  // namespace
}  // namespace softwrist::report
