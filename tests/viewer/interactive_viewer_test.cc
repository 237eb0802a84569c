// `softwrist view` in a real window on a virtual display (Debian's Xvfb through xvfb-run; scripts/test.sh installs
// it): it draws, simulates and saves a screenshot; without a display it fails with a clear error.

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "io/subprocess.h"
#include "io/text_file.h"
#include "physics/units.h"
#include "sim/device.h"
#include "sim/model.h"
#include "sim/model_builder.h"
#include "sim/plugins.h"
#include "sim/wrist_sim.h"
#include "support/scratch_dir_test.h"

namespace softwrist::viewer {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

class ViewUnderXvfb : public testing::ScratchDirTest {};

std::uint32_t big_endian(const std::string& bytes, std::size_t at) {
  std::uint32_t value = 0;
  for (std::size_t i = 0; i < 4; ++i) value = (value << 8) | static_cast<unsigned char>(bytes[at + i]);
  return value;
}

// With the flexor at 137 kPa for 1.5 s of simulated time the wrist flexes (Table RoM: the device reaches ~28 deg),
// and the screenshot is a PNG of the window's size with more than a blank frame in it.
TEST_F(ViewUnderXvfb, DrawsSimulatesAndSavesAScreenshot) {
  if (!fs::exists("/usr/bin/xvfb-run")) GTEST_SKIP() << "xvfb-run is not installed (scripts/test.sh installs it)";
  const fs::path shot = dir_ / "view.png";
  // In the sanitizer build, leak checking is off for this one child: Mesa's llvmpipe leaves 112 bytes in libLLVM,
  // which is unloaded with the GL driver before LeakSanitizer runs, so no suppression can name it. Memory errors
  // are still checked; the viewer's state and overlay are leak-checked in-process (viewer_state_test).
  const char* asan = std::getenv("ASAN_OPTIONS");
  const std::string asan_options = "ASAN_OPTIONS=" + std::string(asan != nullptr ? asan : "") + ":detect_leaks=0";
  const int code = io::run_process(
      {"env", asan_options, "xvfb-run", "-a", "-s", "-screen 0 1280x1024x24", SOFTWRIST_BINARY, "view", "--frames",
       "90", "--screenshot", shot.string(), "--pressures-kpa", "137,0,0,0", "--width", "640", "--height", "480"},
      {.stdout_file = dir_ / "out.txt", .stderr_file = dir_ / "err.txt"});
  ASSERT_EQ(code, 0) << io::read_text_file(dir_ / "err.txt");
  const std::string out = io::read_text_file(dir_ / "out.txt");
  EXPECT_THAT(out, HasSubstr("90 frames, 1.50 s simulated"));
  const std::size_t flexion = out.find("wrist_fe:");
  ASSERT_NE(flexion, std::string::npos) << out;
  EXPECT_GT(std::stod(out.substr(flexion + 9)), 15.0) << out;  // "wrist_fe:   34.9 deg, ..."
  const std::string png = io::read_text_file(shot);
  ASSERT_GT(png.size(), 24u);
  EXPECT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  EXPECT_EQ(big_endian(png, 16), 640u);  // IHDR width, height
  EXPECT_EQ(big_endian(png, 20), 480u);
  EXPECT_GT(png.size(), 20000u);  // a blank 640x480 frame compresses to a few kB
}

// The viewer steps a softwrist model as the experiments do (sim::WristSim): with the flexor's wrist surface an
// ellipse, its wrap cylinder moves with the wrist. The extensor at 137 kPa against the flexor at 100 extends the
// wrist, and the flexor wraps. Stepped by MuJoCo alone, as the viewer did before, the cylinder stays at the neutral
// wrist's equivalent circle, and the wrist ended at -56.0 deg instead of -16.6.
TEST_F(ViewUnderXvfb, ASoftwristModelMovesAsInTheExperiments) {
  if (!fs::exists("/usr/bin/xvfb-run")) GTEST_SKIP() << "xvfb-run is not installed (scripts/test.sh installs it)";
  sim::DeviceDescription device = sim::paper_device();
  device.muscles[sim::kFlexor].wrap_surface.aspect = 1.6;
  const fs::path placement = dir_ / "elliptic.json";
  std::ofstream(placement) << sim::device_to_json(device);
  const char* asan = std::getenv("ASAN_OPTIONS");
  const std::string asan_options = "ASAN_OPTIONS=" + std::string(asan != nullptr ? asan : "") + ":detect_leaks=0";
  const int code = io::run_process(
      {"env", asan_options, "xvfb-run", "-a", "-s", "-screen 0 1280x1024x24", SOFTWRIST_BINARY, "view", "--placement",
       placement.string(), "--frames", "90", "--pressures-kpa", "100,137,0,0", "--width", "320", "--height", "240"},
      {.stdout_file = dir_ / "out.txt", .stderr_file = dir_ / "err.txt"});
  ASSERT_EQ(code, 0) << io::read_text_file(dir_ / "err.txt");
  const std::string out = io::read_text_file(dir_ / "out.txt");
  const std::size_t at = out.find("wrist_fe:");
  ASSERT_NE(at, std::string::npos) << out;
  const double viewed_deg = std::stod(out.substr(at + 9));

  // The viewer's frames: the commands set, then 1/60 s.
  const sim::Model model =
      sim::Model::FromXml(sim::build_model_xml(device), sim::PluginSet::Default(), "the generated model");
  sim::WristSim wrist(model);
  const sim::Data plain = sim::make_data(model);
  for (int frame = 0; frame < 90; ++frame) {
    wrist.command_pressures_kpa({100.0, 137.0, 0.0, 0.0});
    wrist.run(1.0 / 60.0);
    plain->ctrl[0] = 100.0;
    plain->ctrl[1] = 137.0;
    const double end = plain->time + 1.0 / 60.0;
    while (plain->time < end) mj_step(model.get(), plain.get());
  }
  const double experiments_deg = units::rad_to_deg(wrist.angle(physics::WristAxis::kFlexionExtension));
  const int fe = model.id(mjOBJ_JOINT, "wrist_fe");
  const double plain_deg = units::rad_to_deg(plain->qpos[model->jnt_qposadr[fe]]);
  EXPECT_NEAR(viewed_deg, experiments_deg, 0.06) << out;               // the overlay prints a tenth of a degree
  EXPECT_GT(std::abs(plain_deg - experiments_deg), 0.5) << plain_deg;  // what the test tells apart
}

TEST_F(ViewUnderXvfb, WithoutADisplayTheErrorSaysSo) {
  const int code =
      io::run_process({"env", "-u", "DISPLAY", "-u", "WAYLAND_DISPLAY", SOFTWRIST_BINARY, "view", "--frames", "1"},
                      {.stdout_file = dir_ / "out.txt", .stderr_file = dir_ / "err.txt"});
  EXPECT_EQ(code, 1);
  EXPECT_THAT(io::read_text_file(dir_ / "err.txt"), HasSubstr("the viewer needs a display"));
}

}  // namespace
}  // namespace softwrist::viewer
