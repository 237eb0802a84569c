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

  // Selects the NDOF fusion mode (register OPR_MODE 0x3D <- 0x0C; datasheet Table 3-5).
  bool begin() {
    if (read_register(0x00) != 0xA0) return false;  // CHIP_ID
    write_register(0x3D, 0x00);                     // CONFIG mode first
    delay(25);
    write_register(0x3D, 0x0C);  // NDOF
    delay(20);
    ready_ = true;
    return true;
  }

  // The orientation (registers QUA_Data_w_LSB 0x20 .. z_MSB 0x27); false when the chip does not answer.
  bool read(Quaternion* q) {
    if (!ready_ && !begin()) return false;
    Wire.beginTransmission(address_);
    Wire.write(static_cast<uint8_t>(0x20));
    if (Wire.endTransmission() != 0 || Wire.requestFrom(address_, static_cast<uint8_t>(8)) != 8) {
      ready_ = false;
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
    return norm2 > 0.81f && norm2 < 1.21f;
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

  uint8_t address_;
  bool ready_ = false;
};
