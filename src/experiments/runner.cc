#include "experiments/runner.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <stdexcept>
#include <tuple>

#include <fmt/format.h>
#include <unistd.h>

#include "common/parallel_for.h"
#include "io/text_file.h"

namespace softwrist::experiments {
namespace {

// A progress bar on a terminal, or a line per 10 % elsewhere (logs of batch jobs).
class Progress {
 public:
  Progress(std::ostream* out, int total) : out_(out), total_(total), start_(std::chrono::steady_clock::now()) {
    interactive_ = out_ != nullptr && isatty(STDERR_FILENO);
  }
  void update(int done) {
    if (out_ == nullptr || total_ == 0) return;
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    if (interactive_) {
      constexpr int kWidth = 30;
      const int filled = kWidth * done / total_;
      *out_ << fmt::format("\r[{}{}] {}/{} cases {:.1f} s", std::string(filled, '#'), std::string(kWidth - filled, ' '),
                           done, total_, elapsed)
            << (done == total_ ? "\n" : "") << std::flush;
    } else if (int decile = 10 * done / total_; decile > last_decile_) {
      last_decile_ = decile;
      *out_ << fmt::format("{}/{} cases ({} %) {:.1f} s\n", done, total_, 10 * decile, elapsed) << std::flush;
    }
  }

 private:
  std::ostream* out_;
  int total_;
  std::chrono::steady_clock::time_point start_;
  bool interactive_ = false;
  int last_decile_ = -1;
};

// Written to a scratch file renamed over summary.json: its presence marks a finished run (resume refuses one), so a
// kill during the write must not leave a summary cut short.
void write_summary(const std::filesystem::path& out, const nlohmann::json& summary) {
  const auto scratch = out / "summary.json.writing";
  {
    std::ofstream file(scratch);
    file << summary.dump(2) << '\n';
    if (!file) throw std::runtime_error((out / "summary.json").string() + ": cannot write");
  }
  std::filesystem::rename(scratch, out / "summary.json");
}

// The cases that have rows in `log`, in the order they appear.
std::vector<int> cases_in_log(const TrialLog& log) {
  std::vector<int> cases;
  for (std::size_t r = 0; r < log.table.row_count(); ++r) {
    const int index = log.table.integer(r, 0);
    if (cases.empty() || cases.back() != index) cases.push_back(index);
  }
  return cases;
}

// What an existing run directory holds, and how to go on.
std::string existing_run_message(const RunOptions& options, const LogHeader& header) {
  const std::string dir = options.out.string();
  const std::string command = options.command.empty() ? "softwrist run CONFIG --out " + dir : options.command;
  if (std::filesystem::exists(options.out / "summary.json")) {
    return fmt::format(
        "{}: holds a finished run; run it again from the start with\n  {} --overwrite\nor choose "
        "another --out",
        dir, command);
  }
  std::string holds;
  try {
    const TrialLog log = read_log(options.out, kTrialLogName);
    holds = fmt::format("an interrupted run: {} of its {} cases have rows, and no summary", cases_in_log(log).size(),
                        header.case_count);
  } catch (const std::exception& e) {
    holds = fmt::format("a trial log that cannot be read ({})", e.what());
  }
  return fmt::format(
      "{}: holds {}; resume it (its complete cases are kept) with\n  {} --resume\nor run it again "
      "from the start with\n  {} --overwrite",
      dir, holds, command, command);
}

// The rows of an interrupted run's complete cases, and where in `cases` the rest begins. Rows are written in case
// order, so every case before the last one in the log is complete; the last may have been cut short and is run
// again.
std::pair<std::vector<Row>, std::size_t> resumable_rows(const RunOptions& options, const LogHeader& header,
                                                        const std::vector<int>& cases) {
  const std::string dir = options.out.string();
  if (std::filesystem::exists(options.out / "summary.json")) {
    throw std::runtime_error(
        fmt::format("{}: holds a finished run; nothing to resume (--overwrite runs it again)", dir));
  }
  const TrialLog log = read_log(options.out, kTrialLogName);
  const auto differs = [&](const std::string& what) {
    return std::runtime_error(
        fmt::format("{}: its run had another {}; it cannot be resumed with this one (--overwrite "
                    "runs this one from the start)",
                    dir, what));
  };
  if (log.header.config_hash != header.config_hash) throw differs("config");
  if (log.header.model_hash != header.model_hash) throw differs("model");
  if (log.header.shard_index != header.shard_index || log.header.shard_count != header.shard_count)
    throw differs("shard");
  if (log.header.columns.size() != header.columns.size()) throw differs("log format");
  std::map<int, std::size_t> position;
  for (std::size_t i = 0; i < cases.size(); ++i) position[cases[i]] = i;
  std::vector<Row> kept;
  std::size_t last = 0;
  for (std::size_t r = 0; r < log.table.row_count(); ++r) {
    const auto found = position.find(log.table.integer(r, 0));
    if (found == position.end() || found->second < last) {
      throw std::runtime_error(
          fmt::format("{}: line {}: case {} is out of order; the log was not written by an "
                      "interrupted run (--overwrite runs it from the start)",
                      log.table.source(), log.table.line_of(r), log.table.cell(r, 0)));
    }
    last = found->second;
  }
  for (std::size_t r = 0; r < log.table.row_count(); ++r) {
    if (position.at(log.table.integer(r, 0)) >= last) break;
    Row row;
    for (std::size_t c = 0; c < log.table.header().size(); ++c) row.push_back(log.table.cell(r, static_cast<int>(c)));
    kept.push_back(std::move(row));
  }
  return {std::move(kept), log.table.row_count() == 0 ? 0 : last};
}

}  // namespace

std::vector<Column> log_columns(const Experiment& experiment) {
  std::vector<Column> columns = {{"case", "", "index of the case in the experiment"}};
  for (auto& c : experiment.columns()) columns.push_back(c);
  return columns;
}

nlohmann::json summarize_run(const Experiment& experiment, const std::filesystem::path& out, const LogHeader& header) {
  const TrialLog log = read_log(out, kTrialLogName);
  nlohmann::json summary = {{"kind", header.kind},
                            {"config_hash", header.config_hash},
                            {"model_hash", header.model_hash},
                            {"cases", header.case_count}};
  summary.update(experiment.summarize(log.table, out));
  write_summary(out, summary);
  return summary;
}

std::pair<int, int> parse_shard(const std::string& text) {
  int k = 0, n = 0;
  char tail = 0;
  if (std::sscanf(text.c_str(), "%d/%d%c", &k, &n, &tail) != 2 || k < 1 || n < 1 || k > n) {
    throw std::invalid_argument("shard '" + text + "' is not K/N with 1 <= K <= N");
  }
  return {k, n};
}

RunResult run_experiment(const ExperimentConfig& config, const RunOptions& options) {
  const std::unique_ptr<Experiment> experiment = make_experiment(config);
  LogHeader header{.kind = experiment->kind(),
                   .config = config.json,
                   .config_dir = config.base_dir.string(),
                   .config_hash = content_hash(config.json.dump()),
                   .model_hash = experiment->model_hash(),
                   .columns = log_columns(*experiment),
                   .case_count = experiment->case_count(),
                   .shard_index = options.shard_index,
                   .shard_count = options.shard_count};
  std::vector<int> cases;
  for (int i = options.shard_index - 1; i < header.case_count; i += options.shard_count) cases.push_back(i);

  std::vector<Row> kept_rows;
  std::size_t first = 0;  // cases[first...] are run here
  const bool has_log = std::filesystem::exists(options.out / (std::string(kTrialLogName) + ".json"));
  if (has_log && options.existing == ExistingRun::kRefuse) {
    throw std::runtime_error(existing_run_message(options, header));
  }
  if (options.existing == ExistingRun::kResume) {
    if (!has_log) {
      throw std::runtime_error(
          fmt::format("{}: holds no trial log to resume; run without --resume", options.out.string()));
    }
    std::tie(kept_rows, first) = resumable_rows(options, header, cases);
  }
  std::filesystem::remove(options.out / "summary.json");  // a stale summary must not outlive a new run
  const auto writer = options.existing == ExistingRun::kResume
                          ? std::make_unique<LogWriter>(options.out, kTrialLogName, header, kept_rows)
                          : std::make_unique<LogWriter>(options.out, kTrialLogName, header);
  cases.erase(cases.begin(), cases.begin() + static_cast<std::ptrdiff_t>(first));
  // Cases finish out of order on several threads; rows are written in case order as soon as all earlier cases
  // are in, so the file is the same for any number of threads and holds every finished case but a few.
  std::mutex mutex;
  std::map<int, std::vector<Row>> pending;
  std::size_t next_to_write = 0;
  Progress progress(options.progress, static_cast<int>(cases.size()));
  parallel_for(
      static_cast<int>(cases.size()), options.jobs,
      [&](int i) {
        std::vector<Row> rows = experiment->run_case(cases[static_cast<std::size_t>(i)]);
        std::lock_guard lock(mutex);
        pending[i] = std::move(rows);
        while (!pending.empty() && pending.begin()->first == static_cast<int>(next_to_write)) {
          for (auto& row : pending.begin()->second) {
            row.insert(row.begin(), std::to_string(cases[next_to_write]));
            writer->write_row(row);
          }
          pending.erase(pending.begin());
          ++next_to_write;
        }
      },
      [&](int done) { progress.update(done); });

  RunResult result{.cases_run = static_cast<int>(cases.size()),
                   .cases_resumed = static_cast<int>(first),
                   .complete = options.shard_count == 1};
  if (result.complete) result.summary = summarize_run(*experiment, options.out, header);
  return result;
}

RunResult merge_runs(const std::vector<std::filesystem::path>& shard_dirs, const std::filesystem::path& out) {
  if (shard_dirs.empty()) throw std::runtime_error("merge: no shard directories given");
  std::vector<TrialLog> logs;
  for (const auto& dir : shard_dirs) logs.push_back(read_log(dir, kTrialLogName));
  const LogHeader& first = logs.front().header;
  for (std::size_t i = 1; i < logs.size(); ++i) {
    const LogHeader& h = logs[i].header;
    const std::string where = shard_dirs[i].string();
    if (h.config_hash != first.config_hash)
      throw std::runtime_error(where + ": another experiment config than " + shard_dirs[0].string());
    if (h.model_hash != first.model_hash)
      throw std::runtime_error(where + ": another model than " + shard_dirs[0].string());
    if (h.case_count != first.case_count)
      throw std::runtime_error(where + ": another case count than " + shard_dirs[0].string());
  }
  // Every case exactly once; rows in case order (stable within a case).
  std::map<int, std::vector<std::pair<std::size_t, std::size_t>>> rows_by_case;  // case -> (log, row)
  std::map<int, std::string> case_source;
  for (std::size_t l = 0; l < logs.size(); ++l) {
    const io::CsvTable& table = logs[l].table;
    const int c_case = table.column("case");
    std::set<int> seen_here;
    for (std::size_t row = 0; row < table.row_count(); ++row) {
      const int index = table.integer(row, c_case);
      if (index < 0 || index >= first.case_count) {
        throw std::runtime_error(fmt::format("{}:{}: case: {} is not a case of this experiment", table.source(),
                                             table.line_of(row), table.cell(row, c_case)));
      }
      if (case_source.contains(index) && !seen_here.contains(index)) {
        throw std::runtime_error(
            fmt::format("{}:{}: case {} is also in {}", table.source(), table.line_of(row), index, case_source[index]));
      }
      seen_here.insert(index);
      case_source[index] = shard_dirs[l].string();
      rows_by_case[index].emplace_back(l, row);
    }
  }
  std::vector<int> missing;
  for (int i = 0; i < first.case_count && missing.size() < 10; ++i) {
    if (!rows_by_case.contains(i)) missing.push_back(i);
  }
  if (!missing.empty()) {
    throw std::runtime_error(fmt::format("merge: cases missing (first ones: {}); is a shard incomplete or left out?",
                                         fmt::join(missing, ", ")));
  }
  const ExperimentConfig config{.json = first.config,
                                .base_dir = first.config_dir,
                                .source = shard_dirs[0].string() + "/trials.json: config",
                                .name = "merged"};
  const std::unique_ptr<Experiment> experiment = make_experiment(config);
  if (experiment->model_hash() != first.model_hash) {
    throw std::runtime_error("merge: the model or reference data changed since the shards ran (hash " +
                             experiment->model_hash() + ", shards " + first.model_hash + ")");
  }
  LogHeader header = first;
  header.shard_index = header.shard_count = 1;
  std::filesystem::remove(out / "summary.json");
  {
    LogWriter writer(out, kTrialLogName, header);
    for (const auto& [index, rows] : rows_by_case) {
      for (const auto& [l, row] : rows) {
        Row cells;
        for (std::size_t c = 0; c < logs[l].table.header().size(); ++c)
          cells.push_back(logs[l].table.cell(row, static_cast<int>(c)));
        writer.write_row(cells);
      }
    }
  }
  return {.cases_run = first.case_count, .complete = true, .summary = summarize_run(*experiment, out, header)};
}

}  // namespace softwrist::experiments
