#pragma once
// `softwrist view [model.xml]`: the interactive GLFW viewer (viewer/interactive_viewer.h).

#include <ostream>

#include <CLI/CLI.hpp>

namespace softwrist::cli {

void add_view_command(CLI::App& app, std::ostream& out);

}  // namespace softwrist::cli
