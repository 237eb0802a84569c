#pragma once
// `softwrist diagnose-bench --generator independent`: the diagnosis judged on the independent device's data
// (diagnosis_bench/independent_benchmark.h), sharded (--shard K/N, --out) and merged (--merge).

#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

#include "diagnosis/diagnosis.h"

namespace softwrist::cli {

struct IndependentBenchArguments {
  int seeds = 20;
  std::uint64_t first_seed = 1;
  int jobs = 2;
  std::vector<std::string> forms;  // empty: every form
  double trajectory_s = 12.0;
  double min_level = 0.2;
  bool pairs = true;
  std::string shard = "1/1";
  std::string keep;                // keep data sets and diagnoses here
  std::string out;                 // write the summary (with its runs) here, for --merge
  std::vector<std::string> merge;  // summaries of shards to merge instead of running
  std::string calibrate;           // choose the decision settings from the runs; write the record here
  bool redecide = false;           // merged runs decided again at this build's decision settings
  std::string torque_rig = "experiments/independent_device/torque_rig.json";
  std::string prototype = "experiments/independent_device/prototype.json";
  diagnosis::EffectBase effect_base = diagnosis::EffectBase::kBetterOfBoth;  // DiagnosisOptions::effect_base
  diagnosis::RoutingBy routing_by = diagnosis::RoutingBy::kBestModel;        // DiagnosisOptions::routing_by
  bool repeat_mean_test = false;                                             // DiagnosisOptions::repeat_mean_test
  bool rank_beyond_tolerances = false;                                       // DiagnosisOptions::rank_beyond_tolerances
  bool json = false;
};

void run_independent_bench(const IndependentBenchArguments& a, std::ostream& out, std::ostream& err);

}  // namespace softwrist::cli
