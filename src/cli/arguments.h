#pragma once
// Parsing of the command line's compound values ("FROM:TO:STEP", "d1,w1,d2,w2"), with errors that name the option.

#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace softwrist::cli {

// A mistake in the command line: reported as "error: <what>" with exit code 2.
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// One finite number, or UsageError naming `option`.
double parse_number(std::string_view text, std::string_view option);
// Exactly `count` comma-separated finite numbers.
std::vector<double> parse_numbers(std::string_view text, std::size_t count, std::string_view option);
// "FROM:TO:STEP" in degrees: FROM <= TO, STEP > 0, at most 100001 samples, all within [-180, 180]. The last sample
// is TO when (TO - FROM) / STEP is whole (to 1e-9).
std::vector<double> parse_angle_range_deg(std::string_view text, std::string_view option);

}  // namespace softwrist::cli
