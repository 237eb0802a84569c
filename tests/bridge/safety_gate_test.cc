// The safety rules the bridge and the firmware share (bridge/safety_gate.h): the pressure limit, the rate limit,
// the watchdog and the emergency stop.

#include "bridge/safety_gate.h"

#include <algorithm>

#include <gtest/gtest.h>

namespace softwrist::wire {
namespace {

struct Outputs {
  int32_t p[4];
};
Outputs update(SafetyGate& gate, uint32_t now_ms) {
  Outputs o{};
  gate.update(now_ms, o.p);
  return o;
}

TEST(SafetyGate, VentedUntilASessionAndACommand) {
  SafetyGate gate;
  const int32_t request[4] = {500, 0, 0, 0};
  gate.command(request, 0);
  EXPECT_EQ(update(gate, 5).p[0], 0);  // no hello yet
  EXPECT_TRUE(gate.flags(5) & kNoSession);
  gate.start_session(10);
  EXPECT_EQ(update(gate, 20).p[0], 0);  // no command in this session yet
  EXPECT_TRUE(gate.flags(20) & kVented);
}

// 500 kPa asked: 137 kPa at most, reached at the rate limit (full range in 0.1 s), and flagged; lowering is at once.
TEST(SafetyGate, ClampsToTheLimitAndRampsUpAtTheRateLimit) {
  SafetyGate gate;
  gate.start_session(0);
  const int32_t too_much[4] = {5000, -30, 700, 0};
  for (uint32_t t = 0; t <= 100; t += 10) {
    gate.command(too_much, t);
    gate.imu_reading(true, t);
    const Outputs o = update(gate, t);
    EXPECT_EQ(o.p[0], std::min<int32_t>(1370, 137 * static_cast<int32_t>(t) / 10)) << t;  // 137 dkPa per 10 ms
    EXPECT_EQ(o.p[1], 0);
    EXPECT_EQ(o.p[2], std::min<int32_t>(700, 137 * static_cast<int32_t>(t) / 10)) << t;
  }
  EXPECT_TRUE(gate.flags(100) & kLimited);
  const int32_t low[4] = {100, 0, 0, 0};
  gate.command(low, 105);
  gate.imu_reading(true, 105);
  EXPECT_EQ(update(gate, 105).p[0], 100);
  EXPECT_FALSE(gate.flags(105) & kLimited);
}

// No command for longer than the timeout: vented, and it stays vented when commands resume, until a new hello.
TEST(SafetyGate, WatchdogVentsAndLatchesOnAMissingCommand) {
  SafetyGate gate;
  gate.start_session(0);
  const int32_t request[4] = {100, 100, 100, 100};
  for (uint32_t t = 0; t <= 40; t += 10) {
    gate.command(request, t);
    gate.imu_reading(true, t);
    update(gate, t);
  }
  gate.imu_reading(true, 70);
  EXPECT_EQ(update(gate, 70).p[0], 100);  // 30 ms after the last command: still within 40 ms
  EXPECT_EQ(update(gate, 81).p[0], 0);    // 41 ms: vented
  EXPECT_TRUE(gate.flags(81) & kWatchdog);
  gate.command(request, 90);
  gate.imu_reading(true, 90);
  EXPECT_EQ(update(gate, 90).p[0], 0);  // latched
  gate.start_session(100);
  gate.command(request, 100);
  gate.imu_reading(true, 100);
  EXPECT_EQ(update(gate, 110).p[0], 100);
  EXPECT_FALSE(gate.flags(110) & kWatchdog);
}

TEST(SafetyGate, StaleImuVentsToo) {
  SafetyGate gate;
  gate.start_session(0);
  const int32_t request[4] = {100, 0, 0, 0};
  for (uint32_t t = 10; t <= 100; t += 10) {
    gate.command(request, t);
    if (t <= 30) gate.imu_reading(true, t);
    gate.imu_reading(false, t);  // the IMU reports an error: not a valid reading
    const Outputs o = update(gate, t);
    EXPECT_EQ(o.p[0], t <= 70 ? 100 : 0) << t;
  }
  EXPECT_TRUE(gate.flags(100) & kImuFault);
  EXPECT_TRUE(gate.flags(100) & kWatchdog);
}

TEST(SafetyGate, EmergencyStopLatchesUntilTheNextHello) {
  SafetyGate gate;
  gate.start_session(0);
  const int32_t request[4] = {100, 0, 0, 0};
  gate.command(request, 0);
  gate.imu_reading(true, 0);
  EXPECT_EQ(update(gate, 10).p[0], 100);
  gate.emergency_stop();
  gate.command(request, 12);
  gate.imu_reading(true, 12);
  EXPECT_EQ(update(gate, 12).p[0], 0);
  EXPECT_TRUE(gate.flags(12) & kEmergencyStop);
  gate.start_session(20);
  gate.command(request, 20);
  gate.imu_reading(true, 20);
  EXPECT_EQ(update(gate, 30).p[0], 100);
}

}  // namespace
}  // namespace softwrist::wire
