#pragma once
// The time the bridge's safety rules are judged in. On the real exosuit that is the host's monotonic clock
// (SteadyClock); in the lock-step test rig (lockstep_link.h) it is the simulated time the rig advances, so that
// "vented within 50 ms of the cause" is checked exactly, the same on every machine and in every build (issue 27).

#include <chrono>

namespace softwrist::bridge {

class Clock {
 public:
  virtual ~Clock() = default;
  // Seconds on a monotonic scale; only differences mean anything.
  virtual double now_s() const = 0;
};

class SteadyClock final : public Clock {
 public:
  double now_s() const override {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
  }
};

}  // namespace softwrist::bridge
