#pragma once
// The gap diagnosis's commands (docs/diagnosis.md):
//   softwrist import --kind KIND FILE.csv --out DIR          a user's CSV as a trial log
//   softwrist diagnose --real DIR --model PLACEMENT [--out]  diagnosis.json and diagnosis.html
//   softwrist synthesize --model PLACEMENT --out DIR [...]   "real" data from a simulated device with effects injected
//   softwrist diagnose-bench [--seeds N] [--json]           the withheld-effect benchmark of the diagnosis

#include <ostream>

#include <CLI/CLI.hpp>

namespace softwrist::cli {

void add_diagnose_commands(CLI::App& app, std::ostream& out, std::ostream& err);
// `softwrist bench diagnose`: one full diagnosis of the paper-sized data set.
void add_diagnose_bench(CLI::App& bench, std::ostream& out);

}  // namespace softwrist::cli
