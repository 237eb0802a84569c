#pragma once
// `softwrist render`: a PNG of the wrist model at given angles and pressures, rendered offscreen (OSMesa).

#include <ostream>

#include <CLI/CLI.hpp>

namespace softwrist::cli {

void add_render_command(CLI::App& app, std::ostream& out);

}  // namespace softwrist::cli
