#include "io/text_file.h"

#include <fstream>
#include <sstream>
#include <stdexcept>

namespace softwrist::io {

std::string read_text_file(const std::filesystem::path& path) {
  std::ifstream file(path);
  if (!file) throw std::runtime_error(path.string() + ": cannot open");
  std::stringstream text;
  text << file.rdbuf();
  return text.str();
}

}  // namespace softwrist::io
