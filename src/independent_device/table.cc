#include "independent_device/table.h"

#include <algorithm>
#include <iterator>
#include <stdexcept>

#include <fmt/format.h>

namespace softwrist::independent {

std::vector<double> Table::numbers(const std::string& column) const {
  const auto it = std::find(columns.begin(), columns.end(), column);
  if (it == columns.end()) throw std::out_of_range("no column '" + column + "'");
  const auto index = static_cast<std::size_t>(it - columns.begin());
  std::vector<double> out;
  out.reserve(rows.size());
  for (const auto& row : rows) out.push_back(std::get<double>(row[index]));
  return out;
}

std::string Table::csv() const {
  std::string out;
  auto back = std::back_inserter(out);
  for (std::size_t i = 0; i < columns.size(); ++i) fmt::format_to(back, "{}{}", i ? "," : "", columns[i]);
  out += '\n';
  for (const auto& row : rows) {
    for (std::size_t i = 0; i < row.size(); ++i) {
      if (i) out += ',';
      if (const double* d = std::get_if<double>(&row[i]))
        fmt::format_to(back, "{}", *d);
      else
        out += std::get<std::string>(row[i]);
    }
    out += '\n';
  }
  return out;
}

}  // namespace softwrist::independent
