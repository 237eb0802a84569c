// Nothing lost: `softwrist run` killed (SIGKILL) at a random moment leaves every row it wrote readable and equal to
// an uninterrupted run's, says how to resume or re-run, and the resumed run ends with the same log and summary as
// the uninterrupted one (the same seed and config give the same numbers).

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "experiments/trial_log.h"
#include "io/subprocess.h"
#include "io/text_file.h"
#include "support/kill_process.h"
#include "support/scratch_dir_test.h"

namespace softwrist::cli {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

class InterruptedRun : public testing::ScratchDirTest {
 protected:
  // A torque validation of many short cases: long enough to be killed in the middle, short enough for a test.
  fs::path write_config() {
    const fs::path config = dir_ / "torque.json";
    std::ofstream(config) << R"({"format": "softwrist.experiment/1", "kind": "torque_validation",
      "model": ")" SOFTWRIST_SOURCE_DIR R"(/models/paper_device.json", "muscle": "flexor",
      "angles_deg": [-45, -22.5, 0, 22.5, 45, 67.5], "pressures_kpa": [34, 68, 103, 137],
      "repetitions": 5, "seed": 7, "hold_time_s": 8})";
    return config;
  }
  std::vector<std::string> run_args(const fs::path& config, const fs::path& out) {
    return {SOFTWRIST_BINARY, "run", config.string(), "--out", out.string(), "--jobs", "2", "--quiet"};
  }
  int run(std::vector<std::string> args, const std::string& tag) {
    return io::run_process(args, {.stdout_file = dir_ / (tag + ".out"), .stderr_file = dir_ / (tag + ".err")});
  }
  std::string read(const std::string& file) { return io::read_text_file(dir_ / file); }
};

TEST_F(InterruptedRun, KilledRunKeepsItsRowsSaysHowToResumeAndResumesToTheSameNumbers) {
  const fs::path config = write_config();
  const auto start = std::chrono::steady_clock::now();
  ASSERT_EQ(run(run_args(config, dir_ / "whole"), "whole"), 0) << read("whole.err");
  const auto whole_ms = std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() - start);
  const std::string whole_csv = read("whole/trials.csv");
  const std::string whole_summary = read("whole/summary.json");
  const auto whole = experiments::read_log(dir_ / "whole", "trials");

  std::random_device entropy;
  std::mt19937 rng(entropy());
  int killed_midway = 0;  // attempts that killed it after it wrote rows and before it finished
  // A random moment in the first 80 % of an uninterrupted run (the process start included); a run that finished
  // before it (the machine less busy than during the whole run) moves the window earlier, one killed before it wrote
  // anything later, so that how busy the machine is decides only how many attempts it takes.
  long earliest_ms = whole_ms.count() / 20, latest_ms = whole_ms.count() * 4 / 5;
  for (int attempt = 0; attempt < 8 && killed_midway < 3; ++attempt) {
    const fs::path out = dir_ / ("killed" + std::to_string(attempt));
    const auto delay = std::chrono::milliseconds(std::uniform_int_distribution<long>(earliest_ms, latest_ms)(rng));
    SCOPED_TRACE("killed after " + std::to_string(delay.count()) + " ms of a " + std::to_string(whole_ms.count()) +
                 " ms run");
    // Finished first, or killed after its summary (written last, renamed into place) but before the process ended:
    // nothing to test.
    if (!testing::start_and_kill(run_args(config, out), delay) || fs::exists(out / "summary.json")) {
      latest_ms = std::max(earliest_ms, delay.count() * 3 / 4);
      continue;
    }
    if (!fs::exists(out / "trials.json")) {  // killed before it wrote anything
      earliest_ms = std::min(latest_ms, delay.count() * 5 / 4);
      continue;
    }

    // Every row written before the kill reads back, and is the uninterrupted run's row.
    const auto killed = experiments::read_log(out, "trials");
    ASSERT_LE(killed.table.row_count(), whole.table.row_count());
    if (killed.table.row_count() > 0) ++killed_midway;
    for (std::size_t r = 0; r < killed.table.row_count(); ++r) {
      for (std::size_t c = 0; c < whole.table.header().size(); ++c) {
        ASSERT_EQ(killed.table.cell(r, static_cast<int>(c)), whole.table.cell(r, static_cast<int>(c)))
            << "row " << r << ", column " << whole.table.header()[c];
      }
    }

    // Running into it again is refused, with the commands that resume or re-run it.
    const std::string tag = "again" + std::to_string(attempt);
    EXPECT_EQ(run(run_args(config, out), tag), 1);
    const std::string message = read(tag + ".err");
    EXPECT_THAT(message, HasSubstr("holds an interrupted run"));
    EXPECT_THAT(message, HasSubstr("softwrist run " + config.string() + " --out " + out.string() + " --resume"));
    EXPECT_THAT(message, HasSubstr("--overwrite"));

    // Resumed, it ends as the uninterrupted run did: the same log, byte for byte, and the same summary.
    auto resume = run_args(config, out);
    resume.push_back("--resume");
    ASSERT_EQ(run(resume, "resume" + std::to_string(attempt)), 0) << read("resume" + std::to_string(attempt) + ".err");
    EXPECT_EQ(io::read_text_file(out / "trials.csv"), whole_csv);
    EXPECT_EQ(io::read_text_file(out / "summary.json"), whole_summary);
  }
  EXPECT_GE(killed_midway, 1) << "no attempt killed the run between its first row and its end";
}

// A row cut short by the kill (no newline after it) is left out; the rows before it read.
TEST_F(InterruptedRun, RowCutShortIsLeftOutAndNamed) {
  const fs::path config = write_config();
  ASSERT_EQ(run(run_args(config, dir_ / "whole"), "whole"), 0) << read("whole.err");
  std::string csv = read("whole/trials.csv");
  const auto rows = experiments::read_log(dir_ / "whole", "trials").table.row_count();
  csv.resize(csv.size() - 5);  // the last row loses its newline and digits
  std::ofstream(dir_ / "whole" / "trials.csv", std::ios::trunc) << csv;
  const auto log = experiments::read_log(dir_ / "whole", "trials");
  EXPECT_EQ(log.table.row_count(), rows - 1);
  EXPECT_EQ(log.unfinished_line, static_cast<int>(rows) + 1);  // the header is line 1
}

TEST_F(InterruptedRun, ResumeRefusesAnotherConfigAndAFinishedRun) {
  const fs::path config = write_config();
  ASSERT_EQ(run(run_args(config, dir_ / "whole"), "whole"), 0) << read("whole.err");
  auto resume = run_args(config, dir_ / "whole");
  resume.push_back("--resume");
  EXPECT_EQ(run(resume, "finished"), 1);
  EXPECT_THAT(read("finished.err"), HasSubstr("holds a finished run; nothing to resume"));
  EXPECT_EQ(run(run_args(config, dir_ / "whole"), "again"), 1);
  EXPECT_THAT(read("again.err"), HasSubstr("holds a finished run"));

  fs::remove(dir_ / "whole" / "summary.json");
  const std::string text = read("torque.json");
  std::ofstream(config, std::ios::trunc) << text.substr(0, text.find("\"seed\": 7")) +
                                                "\"seed\": 8, \"hold_time_s\": 8}";
  EXPECT_EQ(run(resume, "other"), 1);
  EXPECT_THAT(read("other.err"), HasSubstr("its run had another config"));
}

}  // namespace
}  // namespace softwrist::cli
