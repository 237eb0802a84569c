#pragma once
// The wrist's two angles from the IMU pair (Section Exosuit Prototype: one IMU on the back of the hand, one on the
// back of the forearm, in the same orientation when the wrist is straight). With both IMUs mounted x towards the
// fingers, y towards the ulnar side and z out of the back of the hand, the hand's x axis in the forearm IMU's frame
// gives flexion (the fingers towards the palm, -z) and ulnar deviation (towards +y). The host zeroes both angles at
// the start of a trial, so a small mounting offset does not matter.

#include <math.h>

#include "bno055.h"

inline void wrist_angles_cdeg(const Quaternion& forearm, const Quaternion& hand, int32_t* fe_cdeg, int32_t* ur_cdeg) {
  // q = conj(forearm) * hand: the hand's orientation in the forearm IMU's frame.
  const float w = forearm.w * hand.w + forearm.x * hand.x + forearm.y * hand.y + forearm.z * hand.z;
  const float x = forearm.w * hand.x - forearm.x * hand.w - forearm.y * hand.z + forearm.z * hand.y;
  const float y = forearm.w * hand.y + forearm.x * hand.z - forearm.y * hand.w - forearm.z * hand.x;
  const float z = forearm.w * hand.z - forearm.x * hand.y + forearm.y * hand.x - forearm.z * hand.w;
  // The first column of q's rotation matrix: the hand's x axis.
  const float hx = 1.0f - 2.0f * (y * y + z * z);
  const float hy = 2.0f * (x * y + w * z);
  const float hz = 2.0f * (x * z - w * y);
  const float to_cdeg = 18000.0f / static_cast<float>(M_PI);
  *fe_cdeg = static_cast<int32_t>(lroundf(atan2f(-hz, hx) * to_cdeg));
  *ur_cdeg = static_cast<int32_t>(lroundf(atan2f(hy, sqrtf(hx * hx + hz * hz)) * to_cdeg));
}
