#pragma once
// Starting a program and killing it with SIGKILL at a chosen moment: how the tests make sure that a run killed at
// any time loses nothing it wrote.

#include <chrono>
#include <csignal>
#include <cstdio>
#include <functional>
#include <string>
#include <thread>
#include <vector>

#include <sys/wait.h>
#include <unistd.h>

namespace softwrist::testing {

// Starts argv (argv[0] a path; its output to /dev/null) and kills it with SIGKILL once `ready()` holds (asked
// every 5 ms) or `limit` has passed. Returns whether it was still running then.
inline bool start_and_kill_when(const std::vector<std::string>& argv, const std::function<bool()>& ready,
                                std::chrono::milliseconds limit) {
  const pid_t pid = fork();
  if (pid == 0) {
    std::vector<char*> args;
    for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    if (std::freopen("/dev/null", "w", stdout) == nullptr || std::freopen("/dev/null", "w", stderr) == nullptr)
      _exit(126);
    execv(args[0], args.data());
    _exit(127);
  }
  const auto end = std::chrono::steady_clock::now() + limit;
  bool running = true;
  while (running && !ready() && std::chrono::steady_clock::now() < end) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    running = waitpid(pid, nullptr, WNOHANG) == 0;
  }
  running = running && waitpid(pid, nullptr, WNOHANG) == 0;
  if (running) {
    kill(pid, SIGKILL);
    waitpid(pid, nullptr, 0);
  }
  return running;
}

// Starts argv and kills it with SIGKILL after `delay`. Returns whether it was still running then.
inline bool start_and_kill(const std::vector<std::string>& argv, std::chrono::milliseconds delay) {
  return start_and_kill_when(
      argv, [] { return false; }, delay);
}

}  // namespace softwrist::testing
