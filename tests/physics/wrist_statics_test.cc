// The wrist's statics (physics/wrist_statics.h): the reachable range of Section Range of motion and its clamp.

#include "physics/wrist_statics.h"

#include <gtest/gtest.h>

namespace softwrist::physics {
namespace {

using enum WristAxis;

// Inside the range an angle stays; outside it goes to the nearer end (less the margin); a margin wider than the
// range stops at neutral rather than crossing it. `contains` agrees with the clamp leaving the angle alone.
TEST(ReachableRange, ClampKeepsAnglesInsideTheRangeLessTheMargin) {
  const ReachableRange range{.flexion = 0.5, .extension = 0.9, .ulnar = 0.3, .radial = 0.4};
  EXPECT_EQ(range.clamp(kFlexionExtension, 0.2), 0.2);
  EXPECT_EQ(range.clamp(kFlexionExtension, 1.2), 0.5);
  EXPECT_EQ(range.clamp(kFlexionExtension, -1.2), -0.9);
  EXPECT_DOUBLE_EQ(range.clamp(kUlnarRadial, 1.0, 0.1), 0.2);
  EXPECT_DOUBLE_EQ(range.clamp(kUlnarRadial, -1.0, 0.1), -0.3);
  EXPECT_EQ(range.clamp(kUlnarRadial, 1.0, 0.5), 0.0);
  EXPECT_EQ(range.clamp(kUlnarRadial, -1.0, 0.5), 0.0);
  for (double angle : {-1.0, -0.35, 0.0, 0.25, 0.31, 0.6}) {
    for (WristAxis axis : {kFlexionExtension, kUlnarRadial}) {
      EXPECT_EQ(range.contains(axis, angle), range.clamp(axis, angle) == angle) << angle;
    }
  }
  EXPECT_FALSE(range.contains(kFlexionExtension, 0.45, 0.1));
  EXPECT_TRUE(range.contains(kFlexionExtension, 0.35, 0.1));
}

}  // namespace
}  // namespace softwrist::physics
