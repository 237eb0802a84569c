// The conventions a log's sidecar states (diagnosis/conventions.h): each name read and written back, unknown or
// contradictory values refused naming the file and the field.

#include "diagnosis/conventions.h"

#include <cmath>
#include <fstream>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "support/scratch_dir_test.h"

namespace softwrist::diagnosis {
namespace {

namespace fs = std::filesystem;

TEST(Conventions, TorqueIncludesNamesReadInAnyOrderAndWrittenBack) {
  for (const char* name : {"muscle", "muscle+passive_wrist", "muscle+hand_weight", "muscle+passive_wrist+hand_weight",
                           "baseline_subtracted"}) {
    const auto includes = torque_includes_from_name(name);
    ASSERT_TRUE(includes.has_value()) << name;
    EXPECT_EQ(to_string(*includes), name);
  }
  EXPECT_EQ(torque_includes_from_name("hand_weight+muscle+passive_wrist"),
            (TorqueIncludes{.passive_wrist = true, .hand_weight = true}));
  for (const char* bad : {"", "passive_wrist", "muscle+muscle", "muscle+passive_wrist+passive_wrist", "muscle+gravity",
                          "muscle+", "baseline_subtracted+muscle"}) {
    EXPECT_FALSE(torque_includes_from_name(bad).has_value()) << bad;
  }
}

TEST(Conventions, PostureGivesTheAxisTheHandsWeightTurns) {
  EXPECT_EQ(gravity_axis(Posture::kGravityFe), physics::WristAxis::kFlexionExtension);
  EXPECT_EQ(gravity_axis(Posture::kGravityUr), physics::WristAxis::kUlnarRadial);
  EXPECT_FALSE(gravity_axis(Posture::kHandSupported).has_value());
  for (Posture p : {Posture::kHandSupported, Posture::kGravityFe, Posture::kGravityUr})
    EXPECT_EQ(posture_from_name(to_string(p)), p);
  EXPECT_FALSE(posture_from_name("sideways").has_value());
}

class ConventionsFile : public testing::ScratchDirTest {};

TEST_F(ConventionsFile, ReadBackWhatWasWritten) {
  std::ofstream(dir_ / "rig.json") << "{}";  // only its existence is checked here
  const Conventions c{.posture = Posture::kGravityFe,
                      .torque = {.passive_wrist = true},
                      .angles_zeroed_at_start = true,
                      .angle_resolution = 0.0625 * M_PI / 180.0,
                      .placement = dir_ / "rig.json"};
  nlohmann::json config = {{"other", 1}};
  write_conventions(c, config);
  const Conventions back = conventions_from_config(config, "/elsewhere", "x.json");
  EXPECT_EQ(back.posture, c.posture);
  EXPECT_EQ(back.torque, c.torque);
  EXPECT_TRUE(back.angles_zeroed_at_start);
  EXPECT_NEAR(back.angle_resolution, c.angle_resolution, 1e-15);
  EXPECT_EQ(back.placement, c.placement);

  // A relative placement starts from the log's directory; the old hand_supported switch still reads.
  const Conventions relative =
      conventions_from_config({{"placement", "rig.json"}, {"hand_supported", true}}, dir_, "x.json");
  EXPECT_EQ(relative.placement, dir_ / "rig.json");
  EXPECT_EQ(relative.posture, Posture::kHandSupported);
  // Unstated: the model's frame, the muscle alone, angles as measured.
  const Conventions none = conventions_from_config(nlohmann::json::object(), dir_, "x.json");
  EXPECT_EQ(none.posture, Posture::kGravityUr);
  EXPECT_EQ(none.torque, TorqueIncludes{});
  EXPECT_FALSE(none.angles_zeroed_at_start);
}

TEST_F(ConventionsFile, BadValuesNameTheFileAndTheField) {
  const auto message = [&](const nlohmann::json& config) {
    try {
      conventions_from_config(config, dir_, "logs/sweep.json");
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message({{"posture", "sideways"}}),
            "logs/sweep.json: config.posture: 'sideways' is not hand_supported, gravity_fe or gravity_ur");
  EXPECT_EQ(message({{"posture", 3}}), "logs/sweep.json: config.posture: must be a string");
  EXPECT_EQ(message({{"posture", "gravity_fe"}, {"hand_supported", true}}),
            "logs/sweep.json: config.posture: 'gravity_fe' contradicts hand_supported: true");
  EXPECT_NE(message({{"torque_includes", "everything"}}).find("config.torque_includes: 'everything' is not"),
            std::string::npos);
  EXPECT_EQ(message({{"angles_zeroed_at_start", "yes"}}),
            "logs/sweep.json: config.angles_zeroed_at_start: must be true or false");
  EXPECT_EQ(message({{"angle_resolution_deg", 45}}),
            "logs/sweep.json: config.angle_resolution_deg: 45 deg is coarser than 5 deg");
  EXPECT_EQ(message({{"placement", "no_such_rig.json"}}),
            fmt::format("logs/sweep.json: config.placement: {} is not a file", (dir_ / "no_such_rig.json").string()));
}

}  // namespace
}  // namespace softwrist::diagnosis
