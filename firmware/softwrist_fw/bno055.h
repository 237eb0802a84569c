#pragma once
// The two BNO055 IMUs (Section Exosuit Prototype) over I2C, in their on-chip fusion mode (NDOF): only what the
// firmware needs, the fused orientation quaternion (BNO055 datasheet, section 3.6.5.5: 2^14 LSB per unit).

#include <Arduino.h>
#include <Wire.h>

struct Quaternion {
  float w, x, y, z;
};

class Bno055 {
 public:
  explicit Bno055(uint8_t address) : address_(address) {}

  // Selects the NDOF fusion mode (register OPR_MODE 0x3D <- 0x0C; datasheet Table 3-5) without blocking: CONFIG mode
  // first, NDOF 25 ms later, a reading 20 ms after that (Table 3-6: up to 19 ms into CONFIG, 7 ms out of it). Called
  // by read() until ready, so an IMU that comes back on the bus never holds the loop: the 45 ms this took as two
  // delay()s would outlast the hardware watchdog's 32 ms (and the safety gate's passes).
  void start(uint32_t now_ms) {
    switch (state_) {
      case kAbsent:
        if (read_register(0x00) != 0xA0) return;  // CHIP_ID
        write_register(0x3D, 0x00);               // CONFIG
        break;
      case kConfig:
        if (now_ms - since_ms_ < 25) return;
        write_register(0x3D, 0x0C);  // NDOF
        break;
      case kFusing:
        if (now_ms - since_ms_ < 20) return;
        break;
      case kReady:
        return;
    }
    state_ = static_cast<State>(state_ + 1);
    since_ms_ = now_ms;
  }
  bool ready() const { return state_ == kReady; }

  // The orientation (registers QUA_Data_w_LSB 0x20 .. z_MSB 0x27); false when the chip does not answer or is still
  // starting.
  bool read(Quaternion* q, uint32_t now_ms) {
    if (state_ != kReady) {
      start(now_ms);
      return false;
    }
    Wire.beginTransmission(address_);
    Wire.write(static_cast<uint8_t>(0x20));
    if (Wire.endTransmission() != 0 || Wire.requestFrom(address_, static_cast<uint8_t>(8)) != 8) {
      state_ = kAbsent;
      return false;
    }
    int16_t raw[4];
    for (int i = 0; i < 4; ++i) {
      const uint8_t low = Wire.read(), high = Wire.read();
      raw[i] = static_cast<int16_t>((static_cast<uint16_t>(high) << 8) | low);
    }
    const float scale = 1.0f / 16384.0f;
    q->w = raw[0] * scale;
    q->x = raw[1] * scale;
    q->y = raw[2] * scale;
    q->z = raw[3] * scale;
    // A fused orientation is a unit quaternion: all zeros until fusion runs, and anything far from norm 1 is not a
    // reading (a slave that stopped sending mid-transfer left the bus's last byte in every register; taken as valid,
    // its angles kept the regulators pressurised: found by the firmware in the loop, StuckImuVentsWithin50ms).
    const float norm2 = q->w * q->w + q->x * q->x + q->y * q->y + q->z * q->z;
    const bool unit = norm2 > 0.81f && norm2 < 1.21f;
    // A chip that reset (a brown-out) answers again in CONFIG mode, with zeros for the quaternion: after 100 ms of
    // such readings, start it again (found by the firmware in the loop, ImuThatResetsIsStartedAgain).
    not_unit_ = unit ? 0 : not_unit_ + 1;
    if (not_unit_ >= kRestartAfterNotUnit) {
      not_unit_ = 0;
      state_ = kAbsent;
    }
    return unit;
  }

 private:
  uint8_t read_register(uint8_t reg) {
    Wire.beginTransmission(address_);
    Wire.write(reg);
    if (Wire.endTransmission() != 0 || Wire.requestFrom(address_, static_cast<uint8_t>(1)) != 1) return 0;
    return static_cast<uint8_t>(Wire.read());
  }
  void write_register(uint8_t reg, uint8_t value) {
    Wire.beginTransmission(address_);
    Wire.write(reg);
    Wire.write(value);
    Wire.endTransmission();
  }

  enum State : uint8_t { kAbsent, kConfig, kFusing, kReady };
  static const uint8_t kRestartAfterNotUnit = 10;  // readings in a row, one every 10 ms
  uint8_t address_;
  State state_ = kAbsent;
  uint32_t since_ms_ = 0;
  uint8_t not_unit_ = 0;
};
