#include "cli/run_commands.h"

#include <memory>
#include <thread>

#include <fmt/format.h>

#include "cli/arguments.h"
#include "experiments/runner.h"

namespace softwrist::cli {
namespace {

struct RunOptions {
  std::string config;
  std::string out;
  int jobs = 0;
  std::string shard = "1/1";
  bool quiet = false;
  bool resume = false;
  bool overwrite = false;
};

struct MergeOptions {
  std::string out;
  std::vector<std::string> shards;
};

int default_jobs() { return static_cast<int>(std::max(1u, std::thread::hardware_concurrency())); }

void print_done(std::ostream& out, const std::filesystem::path& dir, const experiments::RunResult& result) {
  out << fmt::format("{}: {} cases, log {}/{}.csv", dir.string(), result.cases_run, dir.string(),
                     experiments::kTrialLogName);
  if (result.complete) out << fmt::format(", summary {}/summary.json", dir.string());
  out << '\n';
}

void run(const RunOptions& options, std::ostream& out, std::ostream& err) {
  std::pair<int, int> shard;
  try {
    shard = experiments::parse_shard(options.shard);
  } catch (const std::invalid_argument& e) {
    throw UsageError(std::string("--shard: ") + e.what());
  }
  if (options.jobs < 0) throw UsageError("--jobs must be >= 1");
  const auto config = experiments::load_experiment_config(options.config);
  std::filesystem::path dir = options.out;
  if (dir.empty()) {
    dir = std::filesystem::path("runs") / config.name;
    if (shard.second > 1) dir += fmt::format("-shard-{}-of-{}", shard.first, shard.second);
  }
  if (options.resume && options.overwrite) throw UsageError("--resume and --overwrite exclude each other");
  std::string command = fmt::format("softwrist run {} --out {}", options.config, dir.string());
  if (shard.second > 1) command += " --shard " + options.shard;
  const auto result =
      experiments::run_experiment(config, {.out = dir,
                                           .existing = options.resume      ? experiments::ExistingRun::kResume
                                                       : options.overwrite ? experiments::ExistingRun::kOverwrite
                                                                           : experiments::ExistingRun::kRefuse,
                                           .command = command,
                                           .jobs = options.jobs > 0 ? options.jobs : default_jobs(),
                                           .shard_index = shard.first,
                                           .shard_count = shard.second,
                                           .progress = options.quiet ? nullptr : &err});
  if (result.cases_resumed > 0)
    out << fmt::format("{}: resumed: {} cases kept from the interrupted run\n", dir.string(), result.cases_resumed);
  print_done(out, dir, result);
  if (!result.complete) {
    out << fmt::format(
        "shard {}/{}: when all shards are done, join them with\n  softwrist merge --out runs/{} "
        "runs/{}-shard-*-of-{}\n",
        shard.first, shard.second, config.name, config.name, shard.second);
  }
}

}  // namespace

void add_run_commands(CLI::App& app, std::ostream& out, std::ostream& err) {
  auto options = std::make_shared<RunOptions>();
  auto* run_command = app.add_subcommand(
      "run", "Run an experiment from its config file (experiments/*.json): trial log, summary.json, curves");
  run_command->add_option("config", options->config, "Experiment config (JSON)")->required()->check(CLI::ExistingFile);
  run_command->add_option("--out", options->out, "Run directory; default runs/<config name>");
  run_command->add_option("--jobs", options->jobs, "Threads for independent cases; default: all cores");
  run_command->add_option("--shard", options->shard,
                          "Run only shard K of N (cases i with i % N == K-1), e.g. $SLURM_ARRAY_TASK_ID/N; "
                          "join the shards with `softwrist merge`");
  run_command->add_flag("--quiet", options->quiet, "No progress output");
  run_command->add_flag("--resume", options->resume,
                        "Go on with an interrupted run in --out: keep its complete cases, run the rest");
  run_command->add_flag("--overwrite", options->overwrite, "Replace a run already in --out");
  run_command->callback([options, &out, &err] { run(*options, out, err); });

  auto merge_options = std::make_shared<MergeOptions>();
  auto* merge = app.add_subcommand("merge",
                                   "Join the run directories of an experiment's shards into one run and "
                                   "write its summary");
  merge->add_option("--out", merge_options->out, "Merged run directory")->required();
  merge->add_option("shards", merge_options->shards, "The shards' run directories")
      ->required()
      ->check(CLI::ExistingDirectory);
  merge->callback([merge_options, &out] {
    std::vector<std::filesystem::path> dirs(merge_options->shards.begin(), merge_options->shards.end());
    print_done(out, merge_options->out, experiments::merge_runs(dirs, merge_options->out));
  });
}

}  // namespace softwrist::cli
