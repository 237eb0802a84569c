#pragma once
// The bridge's safety rules, enforced twice with this one implementation: on the host before a command is sent
// (bridge_plant.h) and on the device before it reaches the regulators (the firmware and the emulator). Freestanding
// C++11 like wire_format.h. Integer units as on the wire: pressures in 0.1 kPa (dkPa), time in ms.
//   - a commanded pressure is clamped to [0, max_dkpa];
//   - the output moves towards it no faster than rate_dkpa_s (venting is never slowed);
//   - the watchdog vents when no valid command, or no valid IMU reading, arrived within timeout_ms, and stays
//     vented until the session is restarted (a stalled host that wakes up must not find the muscles refilling);
//   - an emergency stop vents and latches until the session is restarted (a hello).

#include <stdint.h>

#include "wire_format.h"

namespace softwrist {
namespace wire {

struct SafetyLimits {
  int32_t max_dkpa = 1370;      // the QB3 regulators' 137 kPa (Section Exosuit Prototype)
  int32_t rate_dkpa_s = 13700;  // full range in 0.1 s: no faster than the regulators follow anyway (assumed lag)
  uint32_t timeout_ms = 40;     // ~3 control periods of 14 ms, 4 IMU samples at 100 Hz; vents well within 50 ms
};

class SafetyGate {
 public:
  explicit SafetyGate(const SafetyLimits& limits = SafetyLimits()) : limits_(limits) { reset_outputs(); }

  // A hello: a new session starts vented and waits for its first command.
  void start_session(uint32_t now_ms) {
    reset_outputs();
    session_ = true;
    estop_ = false;
    tripped_ = false;
    last_command_ms_ = now_ms;
    last_imu_ms_ = now_ms;
    last_update_ms_ = now_ms;
  }
  void emergency_stop() {
    estop_ = true;
    reset_outputs();
  }
  // A valid S packet. Out-of-range values are clamped (and flagged), never acted on as given.
  void command(const int32_t requested_dkpa[4], uint32_t now_ms) {
    limited_ = false;
    for (int i = 0; i < 4; ++i) {
      int32_t p = requested_dkpa[i];
      if (p < 0) p = 0;
      if (p > limits_.max_dkpa) p = limits_.max_dkpa;
      if (p != requested_dkpa[i]) limited_ = true;
      target_[i] = p;
    }
    last_command_ms_ = now_ms;
    commanded_ = true;
  }
  void imu_reading(bool valid, uint32_t now_ms) {
    if (valid) last_imu_ms_ = now_ms;
  }

  // Advances to `now_ms` and writes the pressures the regulators may have now [dkPa].
  void update(uint32_t now_ms, int32_t output_dkpa[4]) {
    const uint32_t dt = now_ms - last_update_ms_;
    last_update_ms_ = now_ms;
    if (session_ && !estop_ && commanded_ && timed_out(now_ms)) tripped_ = true;
    if (!session_ || estop_ || tripped_ || !commanded_) {
      reset_outputs();
    } else {
      // In 32 bits when it fits (every pass of the firmware's loop, where a 64-bit division costs the AVR ~0.1 ms).
      const int64_t step = dt < 1000u && limits_.rate_dkpa_s >= 0 && limits_.rate_dkpa_s <= 2000000
                               ? static_cast<int64_t>(limits_.rate_dkpa_s * static_cast<int32_t>(dt) / 1000)
                               : static_cast<int64_t>(limits_.rate_dkpa_s) * dt / 1000;
      for (int i = 0; i < 4; ++i) {
        int64_t next = target_[i];
        if (next > output_[i] + step) {
          next = output_[i] + step;
          limited_ = true;
        }
        output_[i] = static_cast<int32_t>(next);  // decreases at once: letting air out is always safe
      }
    }
    for (int i = 0; i < 4; ++i) output_dkpa[i] = output_[i];
  }

  int32_t flags(uint32_t now_ms) const {
    int32_t f = 0;
    bool vented = true;
    for (int i = 0; i < 4; ++i) vented = vented && output_[i] == 0;
    if (vented) f |= kVented;
    if (estop_) f |= kEmergencyStop;
    if (tripped_) f |= kWatchdog;
    if (session_ && now_ms - last_imu_ms_ > limits_.timeout_ms) f |= kImuFault;
    if (limited_) f |= kLimited;
    if (!session_) f |= kNoSession;
    return f;
  }
  const SafetyLimits& limits() const { return limits_; }

 private:
  bool timed_out(uint32_t now_ms) const {
    return now_ms - last_command_ms_ > limits_.timeout_ms || now_ms - last_imu_ms_ > limits_.timeout_ms;
  }
  void reset_outputs() {
    for (int i = 0; i < 4; ++i) output_[i] = target_[i] = 0;
    commanded_ = false;
  }

  SafetyLimits limits_;
  int32_t target_[4];
  int32_t output_[4];
  bool session_ = false, estop_ = false, commanded_ = false, tripped_ = false, limited_ = false;
  uint32_t last_command_ms_ = 0, last_imu_ms_ = 0, last_update_ms_ = 0;
};

}  // namespace wire
}  // namespace softwrist
