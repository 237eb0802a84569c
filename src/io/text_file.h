#pragma once
// Whole-file reading for every file input (placement files, MJCF, experiment configs, CSV).

#include <filesystem>
#include <string>

namespace softwrist::io {

// The file's contents; std::runtime_error("<path>: cannot open") when it cannot be read.
std::string read_text_file(const std::filesystem::path& path);

}  // namespace softwrist::io
