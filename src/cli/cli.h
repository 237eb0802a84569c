#pragma once
// The `softwrist` command line as a function, so tests run it in-process: exit code 0 on success, 2 on a usage
// or parameter error (message on `err`, naming the option or parameter), 1 on any other failure.

#include <ostream>
#include <string>
#include <vector>

namespace softwrist::cli {

int run_cli(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);

}  // namespace softwrist::cli
