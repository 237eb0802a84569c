#include "experiments/runner.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <map>
#include <mutex>
#include <set>
#include <stdexcept>

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

void write_summary(const std::filesystem::path& out, const nlohmann::json& summary) {
  std::ofstream file(out / "summary.json");
  file << summary.dump(2) << '\n';
  if (!file) throw std::runtime_error((out / "summary.json").string() + ": cannot write");
}

}  // namespace

std::vector<Column> log_columns(const Experiment& experiment) {
  std::vector<Column> columns = {{"case", "", "index of the case in the experiment"}};
  for (auto& c : experiment.columns()) columns.push_back(c);
  return columns;
}

nlohmann::json summarize_run(const Experiment& experiment, const std::filesystem::path& out,
                             const LogHeader& header) {
  const TrialLog log = read_log(out, kTrialLogName);
  nlohmann::json summary = {{"kind", header.kind}, {"config_hash", header.config_hash},
                            {"model_hash", header.model_hash}, {"cases", header.case_count}};
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

  std::filesystem::remove(options.out / "summary.json");  // a stale summary must not outlive a new run
  LogWriter writer(options.out, kTrialLogName, header);
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
            writer.write_row(row);
          }
          pending.erase(pending.begin());
          ++next_to_write;
        }
      },
      [&](int done) { progress.update(done); });

  RunResult result{.cases_run = static_cast<int>(cases.size()), .complete = options.shard_count == 1};
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
    if (h.config_hash != first.config_hash) throw std::runtime_error(where + ": another experiment config than " + shard_dirs[0].string());
    if (h.model_hash != first.model_hash) throw std::runtime_error(where + ": another model than " + shard_dirs[0].string());
    if (h.case_count != first.case_count) throw std::runtime_error(where + ": another case count than " + shard_dirs[0].string());
  }
  // Every case exactly once; rows in case order (stable within a case).
  std::map<int, std::vector<std::pair<std::size_t, std::size_t>>> rows_by_case;  // case -> (log, row)
  std::map<int, std::string> case_source;
  for (std::size_t l = 0; l < logs.size(); ++l) {
    const io::CsvTable& table = logs[l].table;
    const int c_case = table.column("case");
    std::set<int> seen_here;
    for (std::size_t row = 0; row < table.row_count(); ++row) {
      const double value = table.number(row, c_case);
      const int index = static_cast<int>(value);
      if (value != index || index < 0 || index >= first.case_count) {
        throw std::runtime_error(fmt::format("{}:{}: case: {} is not a case of this experiment", table.source(),
                                             table.line_of(row), table.cell(row, c_case)));
      }
      if (case_source.contains(index) && !seen_here.contains(index)) {
        throw std::runtime_error(fmt::format("{}:{}: case {} is also in {}", table.source(), table.line_of(row),
                                             index, case_source[index]));
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
  const ExperimentConfig config{.json = first.config, .base_dir = first.config_dir,
                                .source = shard_dirs[0].string() + "/trials.json: config", .name = "merged"};
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
        for (std::size_t c = 0; c < logs[l].table.header().size(); ++c) cells.push_back(logs[l].table.cell(row, static_cast<int>(c)));
        writer.write_row(cells);
      }
    }
  }
  return {.cases_run = first.case_count, .complete = true, .summary = summarize_run(*experiment, out, header)};
}

}  // namespace softwrist::experiments
