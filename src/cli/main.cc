#include <iostream>
#include <string>
#include <vector>

#include <mujoco/mujoco.h>

#include "cli/cli.h"

int main(int argc, char** argv) {
  // MuJoCo prints its warnings (a diagnosis's trial fit that made a simulation unstable) on stdout unless told
  // otherwise, which put them into the JSON that `--json` prints there: at the program's edge, they go to stderr.
  mju_user_warning = [](const char* message) { std::cerr << "MuJoCo: " << message << "\n"; };
  const std::vector<std::string> args(argv + 1, argv + argc);
  return softwrist::cli::run_cli(args, std::cout, std::cerr);
}
