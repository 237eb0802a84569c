#pragma once
// `softwrist render`: PNGs of the wrist model, rendered offscreen (OSMesa): a pose of a device, the moments of a
// run, or a video of a tracking run (ffmpeg).

#include <ostream>

#include <CLI/CLI.hpp>

namespace softwrist::cli {

void add_render_command(CLI::App& app, std::ostream& out);

}  // namespace softwrist::cli
