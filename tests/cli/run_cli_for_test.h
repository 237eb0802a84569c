#pragma once
// Runs the `softwrist` command line in-process and captures its exit code and output.

#include <sstream>
#include <string>
#include <vector>

#include "cli/cli.h"

namespace softwrist::cli {

struct CliResult {
  int code;
  std::string out, err;
};

inline CliResult run(const std::vector<std::string>& args) {
  std::ostringstream out, err;
  const int code = run_cli(args, out, err);
  return {code, out.str(), err.str()};
}

}  // namespace softwrist::cli
