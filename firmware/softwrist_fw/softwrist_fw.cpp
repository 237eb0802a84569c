// softwrist firmware for the paper's Arduino Uno (Section Exosuit Prototype): sets the four QB3 pressure regulators
// through their low-pass-filtered PWM inputs, reads their pressure monitor outputs and the two BNO055 IMUs at
// 100 Hz, drives the supply valve, and speaks the bridge's line protocol (docs/bridge-protocol.md) with the host.
// The protocol and the safety rules are the host's own headers (src/bridge/wire_format.h, safety_gate.h), so the
// device enforces exactly what the host is tested against.
//
// Wiring (firmware/README.md): PWM 3, 5, 6, 9 -> regulators (flexor, extensor, ulnar, radial); A0-A3 <- their
// pressure monitors (0-5 V for 0-137 kPa); pin 7 -> the supply valve's driver (HIGH opens); pin 8 <- the safety
// switch (closed to ground = run; open cuts the air whatever the host says); I2C: forearm IMU 0x28, hand IMU 0x29.

#include <Arduino.h>
#include <Wire.h>
#include <avr/wdt.h>

#include "bno055.h"
#include "bridge/device_protocol.h"
#include "bridge/pwm_scaling.h"
#include "bridge/safety_gate.h"
#include "bridge/wire_format.h"
#include "wrist_angles.h"

using softwrist::wire::Packet;
using softwrist::wire::SafetyGate;
using softwrist::wire::SafetyLimits;

namespace {

const uint8_t kRegulatorPins[4] = {3, 5, 6, 9};
const uint8_t kMonitorPins[4] = {A0, A1, A2, A3};
const uint8_t kValvePin = 7;
const uint8_t kSafetySwitchPin = 8;
const uint32_t kDataPeriodMs = 10;  // 100 Hz, the BNO055's fusion rate

SafetyGate gate{SafetyLimits()};
softwrist::wire::DeviceProtocol protocol(&gate);
softwrist::wire::LineAssembler lines;
Bno055 forearm_imu(0x28), hand_imu(0x29);
uint32_t last_data_ms = 0;
int32_t fe_cdeg = 0, ur_cdeg = 0;

void send(const Packet& p) {
  char buffer[softwrist::wire::kMaxLine + 2];
  const size_t n = softwrist::wire::format_packet(p, buffer, sizeof buffer);
  Serial.write(reinterpret_cast<const uint8_t*>(buffer), n);
}

// Writes the regulators (0-137 kPa over the PWM's duty) and the valve: open only while the switch is closed and some
// regulator is above zero. A regulator's PWM is rewritten only when its pressure changed: rescaling all four in every
// pass (32-bit divisions, analogWrite) took the mean pass from 0.20 to 0.91 ms (measured on the firmware in the loop).
int32_t written_dkpa[4] = {-1, -1, -1, -1};

void apply_outputs(const int32_t dkpa[4]) {
  bool any = false;
  const bool switch_closed = digitalRead(kSafetySwitchPin) == LOW;
  for (int i = 0; i < 4; ++i) {
    const int32_t p = switch_closed ? dkpa[i] : 0;
    any = any || p > 0;
    if (p == written_dkpa[i]) continue;
    written_dkpa[i] = p;
    // Rounded, not truncated (truncating set every regulator up to one PWM step, 0.54 kPa, low), for each timer's
    // mode, and over the regulators' full scale rather than the safety limit (pwm_scaling.h; found by the firmware in
    // the loop, tests/hil/hil_test.cc, PwmSetsTheNearestStepOnEveryTimer).
    analogWrite(kRegulatorPins[i],
                static_cast<int>(softwrist::wire::pwm_value(p, softwrist::wire::fast_pwm_muscle(i))));
  }
  digitalWrite(kValvePin, any ? HIGH : LOW);
}

}  // namespace

// First thing after any reset, before the C runtime's initialisation (section .init3; avr-libc's <avr/wdt.h>
// documentation): after a watchdog reset the AVR keeps its watchdog running at the shortest period, 16 ms (ATmega328P
// datasheet, 10.9.2: WDRF overrides WDE), which reset the firmware again in its IMU start-up, for ever: found by the
// firmware in the loop (HungFirmwareIsResetByTheHardwareWatchdogAndComesBackVented). An Uno's optiboot clears it
// before the sketch starts; a board flashed without a bootloader, or with an older one, does not.
void clear_watchdog_after_reset() __attribute__((naked, used, section(".init3")));
void clear_watchdog_after_reset() {
  MCUSR = 0;
  wdt_disable();
}

void setup() {
  for (int i = 0; i < 4; ++i) {
    pinMode(kRegulatorPins[i], OUTPUT);
    analogWrite(kRegulatorPins[i], 0);
  }
  pinMode(kValvePin, OUTPUT);
  digitalWrite(kValvePin, LOW);
  pinMode(kSafetySwitchPin, INPUT_PULLUP);
  Serial.begin(115200);
  Wire.begin();
  Wire.setClock(400000);
  // A slave that holds the bus makes the Wire library wait forever by default: give up after 5 ms and reset the bus,
  // so a stuck IMU is an invalid reading (the gate vents within 40 ms), not a hung loop (the hardware watchdog's 32
  // ms, below).
  Wire.setWireTimeout(5000, true);
  // Both IMUs into fusion mode (45 ms), or on until they answer (an absent one starts when read() finds it).
  for (const uint32_t start = millis(); millis() - start < 100 && !(forearm_imu.ready() && hand_imu.ready());) {
    forearm_imu.start(millis());
    hand_imu.start(millis());
  }
  // The AVR's own watchdog: a loop that hangs resets the board within 32 ms (WDTO_30MS: 4096 cycles of its 128 kHz
  // oscillator), and a reset leaves the PWM pins as inputs: the regulators' pull-downs vent them, inside the 50 ms
  // every other fault vents in. The longest pass is 3.6 ms (docs/hil.md); 60 ms (64 ms) vented too late.
  wdt_enable(WDTO_30MS);
}

void loop() {
  wdt_reset();
  const uint32_t now = millis();
  while (Serial.available() > 0) {
    if (!lines.push(static_cast<char>(Serial.read()))) continue;
    Packet reply;
    bool has_reply = false;
    protocol.handle_line(lines.line(), lines.length(), now, &reply, &has_reply);
    if (has_reply) send(reply);
  }
  if (now - last_data_ms >= kDataPeriodMs) {
    last_data_ms = now;
    Quaternion forearm, hand;
    // Both read (or started) every period, so two IMUs that come back start together.
    const bool forearm_valid = forearm_imu.read(&forearm, now);
    const bool valid = hand_imu.read(&hand, now) && forearm_valid;
    if (valid) wrist_angles_cdeg(forearm, hand, &fe_cdeg, &ur_cdeg);
    gate.imu_reading(valid, now);
    int32_t measured[4];
    for (int i = 0; i < 4; ++i) {
      // An ADC code k stands for inputs from k to k + 1 steps of Vref/1024: the middle, (k + 1/2) / 1024 of full
      // scale, rounded (k * max / 1023, truncated, read up to 0.2 kPa low; found by the firmware in the loop).
      const int32_t k = analogRead(kMonitorPins[i]);
      measured[i] = ((2 * k + 1) * static_cast<int32_t>(gate.limits().max_dkpa) + 1024) / 2048;
    }
    send(protocol.data_packet(now, fe_cdeg, ur_cdeg, measured));
  }
  // Every pass, so an emergency stop or a timeout vents within a pass of it: 0.2 ms on average, 3.6 ms at most (the
  // pass that reads both IMUs and sends a data packet), measured on the firmware in the loop (docs/hil.md).
  int32_t outputs[4];
  gate.update(now, outputs);
  apply_outputs(outputs);
}
