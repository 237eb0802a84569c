#pragma once
// Whole-file reading for the sim layer's inputs (placement files, MJCF).

#include <filesystem>
#include <string>

namespace softwrist::sim {

// The file's contents; std::runtime_error("<path>: cannot open") when it cannot be read.
std::string read_text_file(const std::filesystem::path& path);

}  // namespace softwrist::sim
