// The viewer's keys and overlay (viewer/viewer_state.h), without a window.

#include "viewer/viewer_state.h"

#include <GLFW/glfw3.h>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "sim/device.h"
#include "sim/model.h"
#include "sim/model_builder.h"

namespace softwrist::viewer {
namespace {

using ::testing::ElementsAre;
using ::testing::HasSubstr;

TEST(ViewerKeys, EachKeyHasItsCommand) {
  EXPECT_EQ(command_for_key(GLFW_KEY_1, 0)->command, Command::kSelect);
  EXPECT_EQ(command_for_key(GLFW_KEY_4, 0)->actuator, 3);
  EXPECT_EQ(command_for_key(GLFW_KEY_UP, 0)->command, Command::kRaise);
  EXPECT_EQ(command_for_key(GLFW_KEY_UP, GLFW_MOD_SHIFT)->command, Command::kRaiseFinely);
  EXPECT_EQ(command_for_key(GLFW_KEY_DOWN, 0)->command, Command::kLower);
  EXPECT_EQ(command_for_key(GLFW_KEY_DOWN, GLFW_MOD_SHIFT)->command, Command::kLowerFinely);
  EXPECT_EQ(command_for_key(GLFW_KEY_0, 0)->command, Command::kVentAll);
  EXPECT_EQ(command_for_key(GLFW_KEY_SPACE, 0)->command, Command::kTogglePause);
  EXPECT_EQ(command_for_key(GLFW_KEY_BACKSPACE, 0)->command, Command::kReset);
  EXPECT_EQ(command_for_key(GLFW_KEY_V, 0)->command, Command::kNextCamera);
  EXPECT_FALSE(command_for_key(GLFW_KEY_X, 0).has_value());
}

// Pressures step by a tenth (finely a hundredth) of the regulator's range and stay within it; selecting a muscle
// the model lacks changes nothing; reset vents and unpauses.
TEST(ViewerState, KeysStepTheSelectedPressureWithinItsRange) {
  ViewerState state({{"flexor", 0, 137}, {"extensor", 0, 137}});
  state.apply({Command::kRaise});
  state.apply({Command::kRaise});
  state.apply({Command::kRaiseFinely});
  EXPECT_THAT(state.commands_kpa(), ElementsAre(::testing::DoubleNear(28.77, 1e-9), 0.0));
  state.apply({Command::kSelect, 1});
  for (int i = 0; i < 15; ++i) state.apply({Command::kRaise});
  EXPECT_DOUBLE_EQ(state.commands_kpa()[1], 137.0);
  state.apply({Command::kSelect, 7});
  EXPECT_EQ(state.selected(), 1);
  state.apply({Command::kLowerFinely});
  EXPECT_DOUBLE_EQ(state.commands_kpa()[1], 137.0 - 1.37);
  state.apply({Command::kVentAll});
  EXPECT_THAT(state.commands_kpa(), ElementsAre(0.0, 0.0));
  state.apply({Command::kLower});
  EXPECT_DOUBLE_EQ(state.commands_kpa()[1], 0.0);

  state.set_command(0, 500.0);
  EXPECT_DOUBLE_EQ(state.commands_kpa()[0], 137.0);
  EXPECT_THROW(state.set_command(2, 10.0), std::out_of_range);
  EXPECT_FALSE(state.apply({Command::kTogglePause}));
  EXPECT_TRUE(state.paused());
  EXPECT_TRUE(state.apply({Command::kReset}));
  EXPECT_FALSE(state.paused());
  EXPECT_THAT(state.commands_kpa(), ElementsAre(0.0, 0.0));
  EXPECT_EQ(state.camera(), CameraMode::kRadial);
  state.apply({Command::kNextCamera});
  EXPECT_EQ(state.camera(), CameraMode::kPalmar);
  state.apply({Command::kNextCamera});
  EXPECT_EQ(state.camera(), CameraMode::kFree);
  state.apply({Command::kNextCamera});
  EXPECT_EQ(state.camera(), CameraMode::kRadial);
}

// On the generated model: the four fPAM actuators with the regulator's range, and an overlay naming both wrist
// joints and marking the selected muscle.
TEST(ViewerState, RangesAndOverlayComeFromTheModel) {
  const sim::Model model = sim::Model::FromXml(sim::build_model_xml(sim::paper_device()), sim::PluginSet::Default());
  const auto ranges = actuator_ranges(model.get(), 99.0);
  ASSERT_EQ(ranges.size(), 4u);
  EXPECT_EQ(ranges[2].name, "ulnar");
  EXPECT_DOUBLE_EQ(ranges[2].high, 137.0);
  ViewerState state(ranges);
  state.apply({Command::kSelect, 2});
  state.set_command(2, 50.0);
  const sim::Data data = sim::make_data(model);
  data->act[2] = 40.0;
  mj_forward(model.get(), data.get());
  const auto rows = state.overlay(model.get(), data.get());
  ASSERT_EQ(rows.size(), 7u);  // time, two joints, four muscles
  EXPECT_EQ(rows[1].first, "wrist_fe");
  EXPECT_THAT(rows[1].second, HasSubstr("0.0 deg"));
  EXPECT_EQ(rows[5].first, "> 3 ulnar");
  EXPECT_THAT(rows[5].second, HasSubstr("command  50.0, regulated  40.0 kPa"));
  EXPECT_EQ(rows[3].first, "  1 flexor");
}

}  // namespace
}  // namespace softwrist::viewer
