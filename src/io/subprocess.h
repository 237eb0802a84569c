#pragma once
// Running the external programs softwrist relies on (python3 for plots, ffmpeg for videos, chromium in tests)
// without a shell: arguments are passed as they are, so paths with spaces or quotes need no escaping.

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include <sys/types.h>

namespace softwrist::io {

struct ProcessOptions {
  std::filesystem::path stdout_file;  // empty: inherit ours
  std::filesystem::path stderr_file;  // empty: inherit ours
};

// Runs argv[0] (looked up on PATH) and waits for it. Returns its exit status, or 128 + the signal that ended it.
// Throws std::runtime_error("cannot run <program>: <reason>") when it cannot be started (not installed).
int run_process(const std::vector<std::string>& argv, const ProcessOptions& options = {});

// A child process that reads what is written to its standard input (ffmpeg reading raw frames).
class ProcessInput {
 public:
  // Starts argv[0] (looked up on PATH); throws std::runtime_error as run_process does.
  explicit ProcessInput(const std::vector<std::string>& argv, const ProcessOptions& options = {});
  // Closes the input and waits for the child if finish() was not called.
  ~ProcessInput();
  ProcessInput(const ProcessInput&) = delete;
  ProcessInput& operator=(const ProcessInput&) = delete;

  // Throws std::runtime_error when the child has stopped reading (it exited or failed).
  void write(const unsigned char* data, std::size_t size);
  // Closes the input and waits; returns the exit status as run_process does.
  int finish();

 private:
  std::string program_;
  int input_ = -1;
  pid_t pid_ = -1;
};

}  // namespace softwrist::io
