#pragma once
// A video of rendered frames, encoded by Debian's ffmpeg (H.264 in MP4 by default; ffmpeg picks the codec from the
// file's extension). ffmpeg is optional: without it the video fails with a clear error and nothing else does.

#include <filesystem>
#include <memory>

#include "io/subprocess.h"
#include "report/offscreen_renderer.h"

namespace softwrist::report {

class VideoWriter {
 public:
  // Starts ffmpeg. Throws std::runtime_error naming the problem: ffmpeg missing, an odd size (the yuv420p pixel
  // format players expect needs even sides), a frame rate outside 1..120.
  VideoWriter(const std::filesystem::path& path, int width, int height, double frames_per_second);

  // Throws std::runtime_error for a frame of another size, or when ffmpeg has stopped.
  void add_frame(const Image& frame);
  // Waits for ffmpeg to write the file; throws std::runtime_error when it failed. Returns the number of frames.
  int finish();

 private:
  std::filesystem::path path_;
  int width_, height_, frames_ = 0;
  std::unique_ptr<io::ProcessInput> ffmpeg_;
};

}  // namespace softwrist::report
