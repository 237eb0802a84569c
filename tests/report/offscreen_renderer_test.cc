#include "report/offscreen_renderer.h"

#include <unistd.h>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "physics/units.h"
#include "sim/device.h"
#include "sim/model_builder.h"

namespace softwrist::report {
namespace {

struct Counts {
  int red = 0, blue = 0, distinct_rows = 0;
};
Counts count(const Image& image) {
  Counts c;
  for (std::size_t i = 0; i + 2 < image.rgb.size(); i += 3) {
    const int r = image.rgb[i], g = image.rgb[i + 1], b = image.rgb[i + 2];
    if (r > 150 && g < 90 && b < 110) ++c.red;
    if (b > 150 && r < 110 && g < 140) ++c.blue;
  }
  return c;
}

Image render(double flexor_kpa, double others_kpa, View view) {
  const sim::Model model = sim::Model::FromXml(sim::build_model_xml(sim::paper_device()), sim::PluginSet::Default());
  const sim::Data data = sim::make_data(model);
  data->qpos[0] = units::deg_to_rad(20.0);
  data->act[0] = flexor_kpa;
  for (int i = 1; i < 4; ++i) data->act[i] = others_kpa;
  mj_forward(model.get(), data.get());
  OffscreenRenderer renderer(model, 320, 240);
  return renderer.Render(data.get(), view, 137.0);
}

// The muscles are drawn, coloured by their pressure: one muscle at 137 kPa shows red pixels among blue ones, all at
// 0 kPa shows no red, all at 137 kPa no blue.
TEST(OffscreenRenderer, MusclesAreColouredByPressure) {
  const Counts one = count(render(137.0, 0.0, View::kRadial));
  EXPECT_GT(one.red, 30);
  EXPECT_GT(one.blue, 30);
  const Counts none = count(render(0.0, 0.0, View::kPalmar));
  EXPECT_EQ(none.red, 0);
  EXPECT_GT(none.blue, 30);
  const Counts all = count(render(137.0, 137.0, View::kPalmar));
  EXPECT_EQ(all.blue, 0);
  EXPECT_GT(all.red, 30);
}

// Frames reuse the renderer's image (no allocation per frame); shadows and reflections are drawn only when asked for
// (RenderQuality), and they change the picture.
TEST(OffscreenRenderer, ReusesItsImageAndDrawsShadowsOnlyWhenAsked) {
  const sim::Model model = sim::Model::FromXml(sim::build_model_xml(sim::paper_device()), sim::PluginSet::Default());
  const sim::Data data = sim::make_data(model);
  mj_forward(model.get(), data.get());
  OffscreenRenderer plain(model, 320, 240);
  const Image& first = plain.Render(data.get(), View::kPalmar, 137.0);
  const unsigned char* pixels = first.rgb.data();
  const Image unshadowed = first;
  const Image& second = plain.Render(data.get(), View::kPalmar, 137.0);
  EXPECT_EQ(&first, &second);
  EXPECT_EQ(second.rgb.data(), pixels);
  EXPECT_EQ(second.rgb, unshadowed.rgb);  // the same state draws the same picture

  OffscreenRenderer shadowed(model, 320, 240, {.shadows = true, .reflections = true});
  const Image& with_shadows = shadowed.Render(data.get(), View::kPalmar, 137.0);
  int darker = 0;  // the hand's and arm's shadows on the table
  for (std::size_t i = 0; i < unshadowed.rgb.size(); ++i) darker += with_shadows.rgb[i] + 40 < unshadowed.rgb[i];
  EXPECT_GT(darker, 500);
}

TEST(OffscreenRenderer, WritesAPng) {
  const auto path =
      std::filesystem::temp_directory_path() / ("softwrist_render_test_" + std::to_string(::getpid()) + ".png");
  write_png(render(100.0, 20.0, View::kRadial), path);
  std::ifstream file(path, std::ios::binary);
  char magic[8] = {};
  file.read(magic, 8);
  EXPECT_EQ(std::string(magic + 1, 3), "PNG");
  EXPECT_GT(std::filesystem::file_size(path), 1000u);
  std::filesystem::remove(path);
  EXPECT_THROW(write_png(render(0, 0, View::kRadial), "/nonexistent/dir/x.png"), std::runtime_error);
}

}  // namespace
}  // namespace softwrist::report
