// How well the nominal is known (diagnosis/tolerance.h): the tolerance file and each effect's box.

#include "diagnosis/tolerance.h"

#include <fstream>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "sim/device.h"
#include "support/scratch_dir_test.h"

namespace softwrist::diagnosis {
namespace {

using ::testing::HasSubstr;

class ToleranceFileTest : public testing::ScratchDirTest {
 protected:
  std::filesystem::path write(const std::string& text) {
    std::ofstream(dir_ / "tolerances.json") << text;
    return dir_ / "tolerances.json";
  }
  std::string error_of(const std::string& text) {
    try {
      read_tolerances(write(text));
    } catch (const std::exception& e) {
      return e.what();
    }
    return "";
  }
};

TEST_F(ToleranceFileTest, FieldsNotGivenKeepTheirDefaults) {
  const Tolerances t = read_tolerances(write(R"({"r0_fraction": 0.05, "eps_max": 0})"));
  EXPECT_DOUBLE_EQ(t.r0_fraction, 0.05);
  EXPECT_DOUBLE_EQ(t.eps_max, 0.0);
  EXPECT_DOUBLE_EQ(t.wrist_radius_fraction, Tolerances{}.wrist_radius_fraction);
  EXPECT_EQ(to_json(t)["r0_fraction"], 0.05);
}

TEST_F(ToleranceFileTest, FieldsWithAUnitAreReadInItAndHeldInSi) {
  const Tolerances t = read_tolerances(
      write(R"({"anchor_mm": 2, "rest_length_mm": 1, "passive_range_margin_deg": 10, "monitor_offset_kpa": 0.25})"));
  EXPECT_DOUBLE_EQ(t.anchor, 0.002);
  EXPECT_DOUBLE_EQ(t.rest_length, 0.001);
  EXPECT_NEAR(t.passive_range_margin, 10.0 * M_PI / 180.0, 1e-15);
  EXPECT_DOUBLE_EQ(t.monitor_offset, 250.0);
  EXPECT_NEAR(to_json(t)["passive_range_margin_deg"].get<double>(), 10.0, 1e-12);
  EXPECT_DOUBLE_EQ(to_json(Tolerances{})["anchor_mm"].get<double>(), 3.0);
}

TEST_F(ToleranceFileTest, BadFilesNameTheFileAndTheField) {
  EXPECT_THAT(error_of(R"({"r0_fractoin": 0.05})"), HasSubstr("tolerances.json: r0_fractoin: unknown field"));
  EXPECT_THAT(error_of(R"({"wrist_radius_fraction": -0.1})"), HasSubstr("wrist_radius_fraction: must be >= 0"));
  EXPECT_THAT(error_of(R"({"passive_stiffness_fraction": 1.5})"),
              HasSubstr("passive_stiffness_fraction: must be below 1 (a fraction), got 1.5"));
  EXPECT_THAT(error_of(R"({"anchor_mm": 25})"), HasSubstr("anchor_mm: must be below 20"));
  EXPECT_THAT(error_of(R"({"eps_max": "small"})"), HasSubstr("eps_max: must be a number"));
  EXPECT_THAT(error_of("{"), HasSubstr("tolerances.json: not valid JSON"));
}

sim::DeviceDescription paper_device() { return sim::paper_device(); }

TEST(ToleranceBox, EachEffectsBoxAroundTheNominal) {
  const Tolerances t;
  const auto fpam = tolerance_box(EffectId::kFpamParams, paper_device(), t);
  ASSERT_TRUE(fpam.has_value());
  EXPECT_DOUBLE_EQ((*fpam)[0].first, 1.0 - t.r0_fraction);
  EXPECT_DOUBLE_EQ((*fpam)[0].second, 1.0 + t.r0_fraction);
  EXPECT_DOUBLE_EQ((*fpam)[1].first, -t.eps_max);
  const auto lag = tolerance_box(EffectId::kRegulatorLag, paper_device(), t);
  ASSERT_TRUE(lag.has_value());
  const double tau = paper_device().regulator.time_constant;
  EXPECT_NEAR((*lag)[0].second, tau * (1.0 + t.regulator_time_constant_fraction), 1e-12);
  EXPECT_EQ((*lag)[1], std::make_pair(0.0, 0.0));  // no dead time within tolerance: the nominal has none
  const auto passive = tolerance_box(EffectId::kPassiveWrist, paper_device(), t);
  ASSERT_TRUE(passive.has_value());
  EXPECT_EQ((*passive)[2], std::make_pair(0.0, 0.0));  // nor a stiffening it does not have
  // What the nominal does not have at all is never within its tolerance.
  EXPECT_FALSE(tolerance_box(EffectId::kHysteresis, paper_device(), t).has_value());
  EXPECT_FALSE(tolerance_box(EffectId::kImuBias, paper_device(), t).has_value());
  sim::DeviceDescription rigid = paper_device();
  rigid.stretch_mode = physics::StretchMode::kNone;
  EXPECT_FALSE(tolerance_box(EffectId::kMountStretch, rigid, t).has_value());
  EXPECT_TRUE(tolerance_box(EffectId::kMountStretch, paper_device(), t).has_value());
}

TEST(ToleranceBox, NoToleranceIsTheNominalExactly) {
  for (const EffectSpec& spec : effect_catalogue())
    EXPECT_FALSE(tolerance_box(spec.id, paper_device(), Tolerances::none()).has_value()) << spec.name;
}

}  // namespace
}  // namespace softwrist::diagnosis
