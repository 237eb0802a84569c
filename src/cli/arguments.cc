#include "cli/arguments.h"

#include <charconv>
#include <cmath>

#include <fmt/format.h>

namespace softwrist::cli {

double parse_number(std::string_view text, std::string_view option) {
  const auto trimmed_begin = text.find_first_not_of(" \t");
  const auto trimmed_end = text.find_last_not_of(" \t");
  if (trimmed_begin == std::string_view::npos) throw UsageError(fmt::format("{}: empty value", option));
  const std::string_view value = text.substr(trimmed_begin, trimmed_end - trimmed_begin + 1);
  double number = 0.0;
  const auto [end, error] = std::from_chars(value.data(), value.data() + value.size(), number);
  if (error != std::errc() || end != value.data() + value.size() || !std::isfinite(number)) {
    throw UsageError(fmt::format("{}: '{}' is not a finite number", option, value));
  }
  return number;
}

std::vector<double> parse_numbers(std::string_view text, std::size_t count, std::string_view option) {
  std::vector<double> numbers;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = text.find(',', start);
    numbers.push_back(parse_number(text.substr(start, comma - start), option));
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  if (numbers.size() != count) {
    throw UsageError(
        fmt::format("{}: expected {} comma-separated numbers, got {} in '{}'", option, count, numbers.size(), text));
  }
  return numbers;
}

std::vector<double> parse_angle_range_deg(std::string_view text, std::string_view option) {
  const auto first = text.find(':');
  const auto second = first == std::string_view::npos ? first : text.find(':', first + 1);
  if (second == std::string_view::npos || text.find(':', second + 1) != std::string_view::npos) {
    throw UsageError(fmt::format("{}: expected FROM:TO:STEP in degrees, got '{}'", option, text));
  }
  const double from = parse_number(text.substr(0, first), option);
  const double to = parse_number(text.substr(first + 1, second - first - 1), option);
  const double step = parse_number(text.substr(second + 1), option);
  if (step <= 0.0) throw UsageError(fmt::format("{}: STEP must be > 0, got {}", option, step));
  if (from > to) throw UsageError(fmt::format("{}: FROM ({}) must not exceed TO ({})", option, from, to));
  if (from < -180.0 || to > 180.0) {
    throw UsageError(fmt::format("{}: angles must lie within [-180, 180] degrees, got {}:{}", option, from, to));
  }
  const double intervals = (to - from) / step;
  if (intervals > 100000.0) {
    throw UsageError(fmt::format("{}: {} samples is too many (at most 100001)", option, std::floor(intervals) + 1));
  }
  const auto count = static_cast<std::size_t>(std::floor(intervals + 1e-9)) + 1;
  std::vector<double> angles;
  angles.reserve(count);
  for (std::size_t i = 0; i < count; ++i) angles.push_back(from + static_cast<double>(i) * step);
  return angles;
}

}  // namespace softwrist::cli
