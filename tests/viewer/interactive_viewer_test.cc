// `softwrist view` in a real window on a virtual display (Debian's Xvfb through xvfb-run; scripts/test.sh installs
// it): it draws, simulates and saves a screenshot; without a display it fails with a clear error.

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "io/subprocess.h"
#include "io/text_file.h"
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

TEST_F(ViewUnderXvfb, WithoutADisplayTheErrorSaysSo) {
  const int code =
      io::run_process({"env", "-u", "DISPLAY", "-u", "WAYLAND_DISPLAY", SOFTWRIST_BINARY, "view", "--frames", "1"},
                      {.stdout_file = dir_ / "out.txt", .stderr_file = dir_ / "err.txt"});
  EXPECT_EQ(code, 1);
  EXPECT_THAT(io::read_text_file(dir_ / "err.txt"), HasSubstr("the viewer needs a display"));
}

}  // namespace
}  // namespace softwrist::viewer
