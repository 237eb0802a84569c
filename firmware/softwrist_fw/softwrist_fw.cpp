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

#include "bridge/safety_gate.h"
#include "bridge/wire_format.h"
#include "bno055.h"
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
softwrist::wire::LineAssembler lines;
Bno055 forearm_imu(0x28), hand_imu(0x29);
uint16_t host_seq = 0, device_seq = 0;
bool host_seq_seen = false;
uint32_t last_data_ms = 0;
int32_t fe_cdeg = 0, ur_cdeg = 0;

void send(const Packet& p) {
  char buffer[softwrist::wire::kMaxLine + 2];
  const size_t n = softwrist::wire::format_packet(p, buffer, sizeof buffer);
  Serial.write(reinterpret_cast<const uint8_t*>(buffer), n);
}

void reject(uint8_t reason) {
  Packet r;
  r.type = 'R';
  r.seq = device_seq++;
  r.count = 1;
  r.fields[0] = reason;
  send(r);
}

void handle_line(const char* line, size_t length, uint32_t now) {
  Packet p;
  const softwrist::wire::ParseError error = softwrist::wire::parse_line(line, length, &p);
  if (error != softwrist::wire::kOk) return reject(error);
  if (p.type != 'H' && p.type != 'S' && p.type != 'E') return reject(softwrist::wire::kUnknownType);
  // A hello may restart the count (a new host process); anything else must be newer than the last packet.
  if (p.type != 'H' && host_seq_seen && !softwrist::wire::is_newer(p.seq, host_seq)) {
    return reject(softwrist::wire::kOutOfSequence);
  }
  host_seq = p.seq;
  host_seq_seen = true;
  if (p.type == 'H') {
    if (p.fields[0] != softwrist::wire::kProtocolVersion) return reject(softwrist::wire::kOutOfRange);
    gate.start_session(now);
    Packet v;
    v.type = 'V';
    v.seq = device_seq++;
    v.count = 4;
    v.fields[0] = softwrist::wire::kProtocolVersion;
    v.fields[1] = gate.limits().max_dkpa;
    v.fields[2] = gate.limits().rate_dkpa_s;
    v.fields[3] = static_cast<int32_t>(gate.limits().timeout_ms);
    send(v);
  } else if (p.type == 'S') {
    gate.command(p.fields, now);
  } else {
    gate.emergency_stop();
  }
}

// Writes the regulators (0-137 kPa over the PWM's 0-255) and the valve: open only while the switch is closed and
// some regulator is above zero.
void apply_outputs(const int32_t dkpa[4]) {
  bool any = false;
  const bool switch_closed = digitalRead(kSafetySwitchPin) == LOW;
  for (int i = 0; i < 4; ++i) {
    const int32_t p = switch_closed ? dkpa[i] : 0;
    analogWrite(kRegulatorPins[i], static_cast<int>(p * 255L / gate.limits().max_dkpa));
    any = any || p > 0;
  }
  digitalWrite(kValvePin, any ? HIGH : LOW);
}

}  // namespace

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
  forearm_imu.begin();
  hand_imu.begin();
}

void loop() {
  const uint32_t now = millis();
  while (Serial.available() > 0) {
    if (lines.push(static_cast<char>(Serial.read()))) handle_line(lines.line(), lines.length(), now);
  }
  if (now - last_data_ms >= kDataPeriodMs) {
    last_data_ms = now;
    Quaternion forearm, hand;
    const bool valid = forearm_imu.read(&forearm) && hand_imu.read(&hand);
    if (valid) wrist_angles_cdeg(forearm, hand, &fe_cdeg, &ur_cdeg);
    gate.imu_reading(valid, now);
    int32_t outputs[4];
    gate.update(now, outputs);
    apply_outputs(outputs);
    Packet d;
    d.type = 'D';
    d.seq = device_seq++;
    d.count = 8;
    d.fields[0] = static_cast<int32_t>(now);
    d.fields[1] = fe_cdeg;
    d.fields[2] = ur_cdeg;
    for (int i = 0; i < 4; ++i) d.fields[3 + i] = analogRead(kMonitorPins[i]) * static_cast<int32_t>(gate.limits().max_dkpa) / 1023;
    d.fields[7] = gate.flags(now);
    send(d);
  }
}
