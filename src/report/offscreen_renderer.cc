#include "report/offscreen_renderer.h"

#include <GL/osmesa.h>
#include <png.h>

#include <algorithm>
#include <cstdio>
#include <stdexcept>

#include <fmt/format.h>

namespace softwrist::report {

struct OffscreenRenderer::Impl {
  const mjModel* model = nullptr;
  OSMesaContext context = nullptr;
  std::vector<unsigned char> buffer;  // OSMesa's RGBA framebuffer
  int width = 0, height = 0;
  mjvScene scene;
  mjvOption option;
  mjrContext render_context;
  RenderQuality quality;
  Image image;                           // the last frame, reused
  std::vector<unsigned char> bottom_up;  // glReadPixels' rows, reused
};

OffscreenRenderer::OffscreenRenderer(const sim::Model& model, int width, int height, const RenderQuality& quality)
    : impl_(std::make_unique<Impl>()) {
  if (width < 16 || height < 16 || width > 4096 || height > 4096) {
    throw std::runtime_error(fmt::format("render size {}x{} must be within 16..4096", width, height));
  }
  Impl& r = *impl_;
  r.model = model.get();
  r.width = width;
  r.height = height;
  r.quality = quality;
  r.image = {width, height, {}};  // read_pixels sizes its buffers on the first frame and reuses them after
  r.context = OSMesaCreateContextExt(OSMESA_RGBA, 24, 8, 0, nullptr);
  if (r.context == nullptr)
    throw std::runtime_error("OSMesa could not create a rendering context (is libosmesa6 installed?)");
  r.buffer.resize(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 4);
  if (!OSMesaMakeCurrent(r.context, r.buffer.data(), GL_UNSIGNED_BYTE, width, height)) {
    OSMesaDestroyContext(r.context);
    throw std::runtime_error("OSMesa could not make its context current");
  }
  mjv_defaultScene(&r.scene);
  mjv_defaultOption(&r.option);
  mjr_defaultContext(&r.render_context);
  mjv_makeScene(r.model, &r.scene, 2000);
  // The rendering context is made from a shallow copy of the model whose only change is its drawing quality and an
  // offscreen buffer of the frame's size (a 1280x960 multisampled buffer costs memory and clearing): mjr_makeContext
  // only reads the model, and the shared model stays as it is for the viewer and the simulation.
  mjModel drawn = *r.model;
  drawn.vis.quality.numslices = std::max(8, quality.slices);
  drawn.vis.quality.numstacks = std::max(4, quality.slices / 2);
  drawn.vis.global.offwidth = width;
  drawn.vis.global.offheight = height;
  mjr_makeContext(&drawn, &r.render_context, mjFONTSCALE_100);
  mjr_setBuffer(mjFB_OFFSCREEN, &r.render_context);
  if (r.render_context.offWidth < width || r.render_context.offHeight < height) {
    throw std::runtime_error(
        fmt::format("the offscreen buffer OSMesa made ({}x{}) is smaller than the {}x{} asked for (its size limit)",
                    r.render_context.offWidth, r.render_context.offHeight, width, height));
  }
}

OffscreenRenderer::~OffscreenRenderer() {
  mjr_freeContext(&impl_->render_context);
  mjv_freeScene(&impl_->scene);
  OSMesaDestroyContext(impl_->context);
}

const Image& OffscreenRenderer::Render(const mjData* data, View view, double max_pressure_kpa) {
  Impl& r = *impl_;
  mjvCamera camera;
  set_view_camera(view, &camera);
  mjv_updateScene(r.model, const_cast<mjData*>(data), &r.option, nullptr, &camera, mjCAT_ALL, &r.scene);
  r.scene.flags[mjRND_SHADOW] = r.quality.shadows ? 1 : 0;
  r.scene.flags[mjRND_REFLECTION] = r.quality.reflections ? 1 : 0;
  colour_muscles_by_pressure(r.model, data, max_pressure_kpa, &r.scene);
  const mjrRect viewport = {0, 0, r.width, r.height};
  mjr_render(viewport, &r.scene, &r.render_context);
  read_pixels(r.render_context, r.image, r.bottom_up);
  return r.image;
}

void read_pixels(const mjrContext& context, Image& image, std::vector<unsigned char>& bottom_up) {
  const std::size_t row = static_cast<std::size_t>(image.width) * 3;
  image.rgb.resize(row * static_cast<std::size_t>(image.height));
  bottom_up.resize(image.rgb.size());
  mjr_readPixels(bottom_up.data(), nullptr, {0, 0, image.width, image.height}, &context);
  for (int y = 0; y < image.height; ++y) {
    std::copy_n(bottom_up.begin() + static_cast<std::ptrdiff_t>(row * static_cast<std::size_t>(image.height - 1 - y)),
                row, image.rgb.begin() + static_cast<std::ptrdiff_t>(row * static_cast<std::size_t>(y)));
  }
}

Image read_pixels(const mjrContext& context, int width, int height) {
  Image image{width, height, {}};
  std::vector<unsigned char> bottom_up;
  read_pixels(context, image, bottom_up);
  return image;
}

void write_png(const Image& image, const std::filesystem::path& path) {
  std::FILE* file = std::fopen(path.c_str(), "wb");
  if (file == nullptr) throw std::runtime_error(fmt::format("cannot write {}", path.string()));
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png != nullptr ? png_create_info_struct(png) : nullptr;
  if (png == nullptr || info == nullptr || setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    std::fclose(file);
    throw std::runtime_error(fmt::format("libpng failed writing {}", path.string()));
  }
  png_init_io(png, file);
  png_set_IHDR(png, info, static_cast<png_uint_32>(image.width), static_cast<png_uint_32>(image.height), 8,
               PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  for (int y = 0; y < image.height; ++y) {
    png_write_row(png, image.rgb.data() + static_cast<std::size_t>(y) * static_cast<std::size_t>(image.width) * 3);
  }
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  if (std::fclose(file) != 0) throw std::runtime_error(fmt::format("cannot write {}", path.string()));
}

}  // namespace softwrist::report
