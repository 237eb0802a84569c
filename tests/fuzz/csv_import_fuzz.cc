// Fuzz target: `softwrist import` of each kind (diagnosis/csv_import.h) on a user's CSV, in memory. The first byte
// chooses the kind and --hand-supported, the rest is the file. A file is either rejected with an error naming it
// (with the line and column where there is one), or accepted as a log whose every number is finite and whose
// trials the diagnosis reads.

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "diagnosis/csv_import.h"
#include "diagnosis/real_data.h"
#include "fuzz_check.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace softwrist;
  if (size == 0) return 0;
  static const char* const kKinds[] = {"torque-sweep", "rom", "tensile", "trajectory"};
  diagnosis::ImportOptions options{.kind = kKinds[data[0] % 4], .hand_supported = (data[0] & 4) != 0};
  const std::string text(reinterpret_cast<const char*>(data + 1), size - 1);
  experiments::TrialLog log;
  try {
    log = diagnosis::import_table(io::CsvTable::Parse(text, "user.csv"), options);
  } catch (const std::runtime_error& e) {
    fuzz::check_names_source(e.what(), "user.csv");
    return 0;
  }
  FUZZ_CHECK(log.table.row_count() > 0);
  for (std::size_t r = 0; r < log.table.row_count(); ++r) {
    for (std::size_t c = 0; c < log.table.header().size(); ++c) {
      const std::string& name = log.table.header()[c];
      if (name == "muscle" || name == "direction") continue;
      FUZZ_CHECK(std::isfinite(log.table.number(r, static_cast<int>(c))));
    }
  }
  const auto trials = diagnosis::trials_from_log(log, "fuzz");
  FUZZ_CHECK(!trials.empty());
  for (const auto& trial : trials) FUZZ_CHECK(trial.size() > 0, "an empty trial %s", trial.name.c_str());
  return 0;
}
