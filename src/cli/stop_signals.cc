#include "cli/stop_signals.h"

#include <pthread.h>

#include <ctime>

namespace softwrist::cli {

StopSignals::StopSignals() {
  sigemptyset(&set_);
  sigaddset(&set_, SIGINT);
  sigaddset(&set_, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &set_, &previous_);
  watcher_ = std::thread([this] {
    const timespec poll_interval{0, 50'000'000};  // 50 ms: how soon the destructor's join returns
    while (!done_.load()) {
      if (sigtimedwait(&set_, nullptr, &poll_interval) > 0) requested.store(true);
    }
  });
}

StopSignals::~StopSignals() {
  done_.store(true);
  watcher_.join();
  pthread_sigmask(SIG_SETMASK, &previous_, nullptr);
}

}  // namespace softwrist::cli
