#include "io/json_reader.h"

namespace softwrist::io {

nlohmann::json parse_json(const std::string& text, const std::string& source) {
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    // parse_error, and out_of_range for a number beyond a double ("1e999"): found by tests/fuzz/placement_fuzz.cc.
    throw std::runtime_error(fmt::format("{}: not valid JSON: {}", source, e.what()));
  }
}

}  // namespace softwrist::io
