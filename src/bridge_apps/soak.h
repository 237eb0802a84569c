#pragma once
// The long trial (`softwrist soak`): tracking through the bridge against the device emulator for a long time (an
// hour by default), over a link that breaks at random (line_faults.h: cuts, garbage both ways, stalls). Each
// hardware trial runs until a fault ends it; the next one starts on the link as it then is. It runs on one of two
// clocks:
//   real time   the emulator on its pseudo-terminal and a relay (fault_relay.h) on threads: what a machine's
//               scheduling does to the loop is part of what is measured, so its vent times are figures of this
//               host, not a property of the device;
//   simulated   the lock-step rig (lockstep_link.h): one thread, the same trials and faults, every time exact and
//               the same on every machine (what the tests check).
// Checked throughout:
//   - every fault ends with the device vented within 50 ms of its onset (the device's own vent record);
//   - every trial's log reads back whole: rows in time order within each run, as many as bridge.json counts, no
//     row cut short, the fault recorded;
//   - memory stays flat: the heap in use (mallinfo2) and the resident set, sampled through the soak.

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bridge_apps/device_emulator.h"
#include "bridge_apps/line_faults.h"
#include "experiments/experiment.h"

namespace softwrist::bridge {

struct SoakOptions {
  double duration_s = 3600.0;
  std::filesystem::path out;  // one directory per trial: trial_0001, ...; and soak.json
  LineFaultOptions faults;
  bool simulated_time = false;     // the lock-step rig instead of real time
  double vent_deadline_s = 0.050;  // from a fault's onset to the device vented
  double memory_sample_s = 30.0;
  std::ostream* progress = nullptr;
};

struct FaultOutcome {
  InjectedFault fault;
  double onset_s = 0.0;                // since the soak began
  std::optional<double> vent_after_s;  // onset to vented (0 when it was vented already); none: never vented
  std::string vent_cause;
};

struct MemorySample {
  double t_s = 0.0;
  std::size_t heap_bytes = 0;      // in use (mallinfo2 uordblks + hblkhd)
  std::size_t resident_bytes = 0;  // /proc/self/statm
};

struct SoakTrial {
  std::filesystem::path dir;
  long rows = 0;
  int runs_completed = 0;
  std::string fault;    // what ended it
  std::string problem;  // what is wrong with its log; empty when it is whole
};

struct SoakResult {
  double duration_s = 0.0;
  bool simulated_time = false;
  std::vector<SoakTrial> trials;
  std::vector<FaultOutcome> faults;
  std::vector<MemorySample> memory;
  EmulatorStats emulator;
  std::vector<std::string> failures;  // each broken check, said in words; empty: the soak passed
  bool passed() const { return failures.empty(); }
};

// Runs the tracking experiment `config` on an emulated device (`emulator`) over a faulty link for
// options.duration_s (of real or simulated time). Throws std::runtime_error for a config that is not a tracking
// experiment.
SoakResult run_soak(const experiments::ExperimentConfig& config, const EmulatorConfig& emulator,
                    const SoakOptions& options);

nlohmann::json to_json(const SoakResult& result);

}  // namespace softwrist::bridge
