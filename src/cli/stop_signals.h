#pragma once
// SIGINT and SIGTERM as a flag, for commands that must stop cleanly (vent the exosuit, close the log) instead of
// dying: while a StopSignals lives, the two signals are blocked in this thread (and in threads it starts later) and
// a watcher thread takes them with sigtimedwait and sets `requested`. No handler and no global flag.

#include <atomic>
#include <csignal>
#include <thread>

namespace softwrist::cli {

class StopSignals {
 public:
  StopSignals();
  ~StopSignals();
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;

  std::atomic<bool> requested{false};

 private:
  sigset_t set_{}, previous_{};
  std::atomic<bool> done_{false};
  std::thread watcher_;
};

}  // namespace softwrist::cli
