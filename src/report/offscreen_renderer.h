#pragma once
// Headless rendering of the wrist model with OSMesa (no display, no GPU): MuJoCo's own renderer drawing into an
// OSMesa software context, each muscle coloured by its regulated pressure (blue at 0, red at the regulator's
// maximum). Cameras like the paper's figures: the radial view for flexion/extension (Fig. Overview d-e), the palmar
// view for ulnar/radial deviation (Fig. Overview b-c).

#include <filesystem>
#include <memory>
#include <vector>

#include <mujoco/mujoco.h>

#include "report/scene_style.h"
#include "sim/model.h"

namespace softwrist::report {

struct Image {
  int width = 0, height = 0;
  std::vector<unsigned char> rgb;  // row-major, top row first
};

// What a frame costs on llvmpipe (2 cores, 640x480, `softwrist bench render`): shadows more than halve the frame
// rate, and each geom's tessellation counts more than the pixels. Reports and videos draw without shadows or
// reflections and with 16 slices per round geom unless asked; the interactive viewer keeps the model's own look.
struct RenderQuality {
  bool shadows = false;
  bool reflections = false;
  int slices = 16;  // around a sphere, capsule or cylinder (MuJoCo's <quality numslices>; its default is 28)
};

class OffscreenRenderer {
 public:
  // Creates the OSMesa context and MuJoCo's rendering context. Throws std::runtime_error with a clear message when
  // OSMesa cannot create a context.
  OffscreenRenderer(const sim::Model& model, int width, int height, const RenderQuality& quality = {});
  ~OffscreenRenderer();
  OffscreenRenderer(const OffscreenRenderer&) = delete;
  OffscreenRenderer& operator=(const OffscreenRenderer&) = delete;

  // Renders the state in `data` (positions and activations as they are; call mj_forward first). The image is the
  // renderer's own, overwritten by the next frame (no allocation per frame); copy it to keep it.
  const Image& Render(const mjData* data, View view, double max_pressure_kpa);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The current buffer of a MuJoCo rendering context (offscreen or window), top row first.
Image read_pixels(const mjrContext& context, int width, int height);
// The same into `image` (sized width x height), through `bottom_up` (a scratch buffer), reusing both.
void read_pixels(const mjrContext& context, Image& image, std::vector<unsigned char>& bottom_up);

// Writes an 8-bit RGB PNG (libpng). Throws std::runtime_error naming the file on failure.
void write_png(const Image& image, const std::filesystem::path& path);

}  // namespace softwrist::report
