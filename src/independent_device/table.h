#pragma once
// A CSV table as the rigs log it: a header row, comma-separated cells, numbers in shortest round-trip form.

#include <string>
#include <variant>
#include <vector>

namespace softwrist::independent {

using Cell = std::variant<double, std::string>;

struct Table {
  std::vector<std::string> columns;
  std::vector<std::vector<Cell>> rows;

  // The numbers of one column, in row order (throws std::out_of_range for an unknown column).
  std::vector<double> numbers(const std::string& column) const;
  std::string csv() const;
};

}  // namespace softwrist::independent
