#pragma once
// The regulators' setpoints as the Uno's 8-bit PWM carries them (firmware/README.md): a setpoint becomes an
// analogWrite value, and the value a duty of the regulators' full scale (0-10 V for 0-137 kPa after the filter and
// buffer). Pins 3 and 9 (flexor, radial) sit on timers 2 and 1, which Arduino runs in phase-correct PWM (duty v / 255);
// pins 5 and 6 (extensor, ulnar) on timer 0 in fast PWM (duty (v + 1) / 256; 0 is written as the pin LOW). Shared by
// the firmware and the device emulator, so the emulator's regulators see the firmware's 0.54 kPa steps. Freestanding
// C++11 like wire_format.h.

#include <stdint.h>

namespace softwrist {
namespace wire {

const int32_t kRegulatorFullScaleDkpa = 1370;  // 137 kPa at full duty, whatever the safety limit

// Whether muscle `m` (flexor 0, extensor 1, ulnar 2, radial 3) is driven by timer 0's fast PWM.
inline bool fast_pwm_muscle(int m) { return m == 1 || m == 2; }

// The analogWrite value nearest to `dkpa` (0 .. full scale).
inline int32_t pwm_value(int32_t dkpa, bool fast) {
  const int32_t full = kRegulatorFullScaleDkpa;
  if (dkpa <= 0) return 0;
  if (dkpa >= full) return 255;
  const int32_t v = fast ? (dkpa * 256L + full / 2) / full - 1 : (dkpa * 255L + full / 2) / full;
  return v < 0 ? 0 : v;
}

// The setpoint [kPa] a written value gives (analogWrite writes 0 as LOW and 255 as HIGH).
inline double pwm_setpoint_kpa(int32_t v, bool fast) {
  const double full_kpa = kRegulatorFullScaleDkpa / 10.0;
  if (v <= 0) return 0.0;
  if (v >= 255) return full_kpa;
  return full_kpa * (fast ? (v + 1) / 256.0 : v / 255.0);
}

}  // namespace wire
}  // namespace softwrist
