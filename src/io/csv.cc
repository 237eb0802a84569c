#include "io/csv.h"

#include <charconv>
#include <cmath>
#include <stdexcept>
#include <system_error>

#include "io/text_file.h"

namespace softwrist::io {
namespace {

std::string_view trim(std::string_view text) {
  const auto first = text.find_first_not_of(" \t\r");
  if (first == std::string_view::npos) return {};
  const auto last = text.find_last_not_of(" \t\r");
  return text.substr(first, last - first + 1);
}

std::runtime_error error_at(const std::string& source, int line, const std::string& problem) {
  return std::runtime_error(source + ":" + std::to_string(line) + ": " + problem);
}

std::vector<std::string> split_cells(std::string_view line, const std::string& source, int line_number) {
  if (line.find('"') != std::string_view::npos) {
    throw error_at(source, line_number, "quoted cells are not supported");
  }
  std::vector<std::string> cells;
  std::size_t start = 0;
  while (true) {
    const auto comma = line.find(',', start);
    cells.emplace_back(trim(line.substr(start, comma == std::string_view::npos ? line.npos : comma - start)));
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  return cells;
}

}  // namespace

CsvTable CsvTable::Parse(const std::string& text, const std::string& source) {
  CsvTable table;
  table.source_ = source;
  std::size_t position = 0;
  int line_number = 0;
  bool have_header = false;
  while (position < text.size()) {
    const auto end = text.find('\n', position);
    const std::string_view line =
        std::string_view(text).substr(position, end == std::string::npos ? std::string::npos : end - position);
    position = end == std::string::npos ? text.size() : end + 1;
    ++line_number;
    const std::string_view content = trim(line);
    if (content.empty() || content.front() == '#') continue;
    auto cells = split_cells(content, source, line_number);
    if (!have_header) {
      for (std::size_t i = 0; i < cells.size(); ++i) {
        if (cells[i].empty())
          throw error_at(source, line_number, "header: column " + std::to_string(i + 1) + " has no name");
        for (std::size_t j = 0; j < i; ++j) {
          if (cells[j] == cells[i])
            throw error_at(source, line_number, "header: column '" + cells[i] + "' appears twice");
        }
      }
      table.header_ = std::move(cells);
      have_header = true;
      continue;
    }
    if (cells.size() != table.header_.size()) {
      throw error_at(
          source, line_number,
          "expected " + std::to_string(table.header_.size()) + " cells, found " + std::to_string(cells.size()));
    }
    table.rows_.push_back(std::move(cells));
    table.lines_.push_back(line_number);
  }
  if (!have_header) throw std::runtime_error(source + ": empty file (no header row)");
  return table;
}

CsvTable CsvTable::Read(const std::filesystem::path& path) { return Parse(read_text_file(path), path.string()); }

int CsvTable::find_column(std::string_view name) const {
  for (std::size_t i = 0; i < header_.size(); ++i) {
    if (header_[i] == name) return static_cast<int>(i);
  }
  return -1;
}

int CsvTable::column(std::string_view name) const {
  const int index = find_column(name);
  if (index < 0) {
    std::string columns;
    for (const auto& h : header_) columns += (columns.empty() ? "" : ", ") + h;
    throw std::runtime_error(source_ + ": missing column '" + std::string(name) + "' (columns: " + columns + ")");
  }
  return index;
}

double CsvTable::number(std::size_t row, int column_index) const {
  const std::string& text = rows_[row][column_index];
  const auto problem = [&](const std::string& what) {
    return error_at(source_, lines_[row], header_[column_index] + ": " + what + ": '" + text + "'");
  };
  if (text.empty()) throw problem("empty cell");
  double value = 0.0;
  const char* begin = text.data();
  if (*begin == '+') ++begin;  // from_chars does not take a leading '+'
  const auto [end, ec] = std::from_chars(begin, text.data() + text.size(), value);
  if (ec != std::errc() || end != text.data() + text.size()) throw problem("not a number");
  if (!std::isfinite(value)) throw problem("not a finite number");
  return value;
}

int CsvTable::integer(std::size_t row, int column_index) const {
  const double value = number(row, column_index);
  // Checked before the cast: a double beyond int's range cast to int is undefined (found by the csv_import fuzzer).
  if (!(value >= -2147483648.0 && value <= 2147483647.0) || value != std::floor(value)) {
    throw error_at(source_, lines_[row],
                   header_[column_index] + ": not a whole number in int's range: '" + rows_[row][column_index] + "'");
  }
  return static_cast<int>(value);
}

CsvTable CsvTable::select(const std::vector<int>& columns, std::vector<std::string> names) const {
  if (columns.size() != names.size()) throw std::logic_error(source_ + ": select: a name for each column");
  CsvTable table;
  table.source_ = source_;
  table.header_ = std::move(names);
  table.lines_ = lines_;
  for (const auto& row : rows_) {
    std::vector<std::string> cells;
    for (int c : columns) cells.push_back(row.at(static_cast<std::size_t>(c)));
    table.rows_.push_back(std::move(cells));
  }
  return table;
}

CsvWriter::CsvWriter(const std::filesystem::path& path, std::vector<std::string> header)
    : path_(path), columns_(header.size()), file_(path) {
  if (!file_) throw std::runtime_error(path.string() + ": cannot create");
  write_row(header);
}

CsvWriter::CsvWriter(const std::filesystem::path& path, std::vector<std::string> header, Append)
    : path_(path), columns_(header.size()), file_(path, std::ios::app) {
  if (!file_) throw std::runtime_error(path.string() + ": cannot append");
}

void CsvWriter::write_row(const std::vector<std::string>& cells) {
  if (cells.size() != columns_) {
    throw std::logic_error(path_.string() + ": row of " + std::to_string(cells.size()) + " cells for " +
                           std::to_string(columns_) + " columns");
  }
  for (std::size_t i = 0; i < cells.size(); ++i) file_ << (i ? "," : "") << cells[i];
  file_ << '\n';
  file_.flush();
  if (!file_) throw std::runtime_error(path_.string() + ": write failed");
}

std::string format_number(double value) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, result.ptr);
}

}  // namespace softwrist::io
