#include "report/video_writer.h"

#include <stdexcept>

#include <fmt/format.h>

namespace softwrist::report {

VideoWriter::VideoWriter(const std::filesystem::path& path, int width, int height, double frames_per_second)
    : path_(path), width_(width), height_(height) {
  if (width % 2 != 0 || height % 2 != 0) {
    throw std::runtime_error(fmt::format("video: {}x{}: width and height must be even", width, height));
  }
  if (!(frames_per_second >= 1.0 && frames_per_second <= 120.0)) {
    throw std::runtime_error(fmt::format("video: {} frames per second is outside 1..120", frames_per_second));
  }
  try {
    ffmpeg_ = std::make_unique<io::ProcessInput>(std::vector<std::string>{
        "ffmpeg", "-hide_banner", "-loglevel", "error", "-y",                              //
        "-f", "rawvideo", "-pix_fmt", "rgb24", "-s", fmt::format("{}x{}", width, height),  // our frames on stdin
        "-r", fmt::format("{}", frames_per_second), "-i", "-",                             //
        "-an", "-pix_fmt", "yuv420p", path.string()});
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(fmt::format("video: {} (install Debian's ffmpeg)", e.what()));
  }
}

void VideoWriter::add_frame(const Image& frame) {
  if (frame.width != width_ || frame.height != height_) {
    throw std::runtime_error(
        fmt::format("video: frame {}x{} in a {}x{} video", frame.width, frame.height, width_, height_));
  }
  try {
    ffmpeg_->write(frame.rgb.data(), frame.rgb.size());
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(fmt::format("video {}: {}", path_.string(), e.what()));
  }
  ++frames_;
}

int VideoWriter::finish() {
  const int code = ffmpeg_->finish();
  if (code != 0) throw std::runtime_error(fmt::format("video {}: ffmpeg exited with {}", path_.string(), code));
  return frames_;
}

}  // namespace softwrist::report
