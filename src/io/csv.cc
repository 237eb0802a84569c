#include "io/csv.h"

#include <algorithm>
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

// One quoted cell (RFC 4180: '""' is a quote inside it) starting at line[start] == '"', unquoted into `cell`; returns
// where it ends (at the comma after it, or the line's end). Spreadsheets quote text cells, and some every header.
std::size_t quoted_cell(std::string_view line, std::size_t start, std::string& cell, const std::string& source,
                        int line_number) {
  std::size_t i = start + 1;
  while (true) {
    const auto quote = line.find('"', i);
    if (quote == std::string_view::npos)
      throw error_at(source, line_number, "a quoted cell does not end on its line (cells spanning lines are not read)");
    cell.append(line.substr(i, quote - i));
    if (quote + 1 < line.size() && line[quote + 1] == '"') {
      cell.push_back('"');
      i = quote + 2;
      continue;
    }
    const auto comma = line.find(',', quote + 1);
    const std::string_view after =
        line.substr(quote + 1, comma == std::string_view::npos ? line.npos : comma - quote - 1);
    if (!trim(after).empty()) throw error_at(source, line_number, "text after a quoted cell's closing quote");
    return comma == std::string_view::npos ? line.size() : comma;
  }
}

std::vector<std::string> split_cells(std::string_view line, const std::string& source, int line_number) {
  std::vector<std::string> cells;
  std::size_t start = 0;
  while (true) {
    const auto first = line.find_first_not_of(" \t", start);
    std::size_t end;
    if (first != std::string_view::npos && line[first] == '"') {
      std::string cell;
      end = quoted_cell(line, first, cell, source, line_number);
      cells.push_back(std::move(cell));
    } else {
      end = std::min(line.find(',', start), line.size());
      const std::string_view cell = trim(line.substr(start, end - start));
      if (cell.find('"') != std::string_view::npos)
        throw error_at(source, line_number, "a quote inside an unquoted cell: '" + std::string(cell) + "'");
      cells.emplace_back(cell);
    }
    if (end >= line.size()) break;
    start = end + 1;
  }
  return cells;
}

// A header without a comma that a semicolon or tab separates: a spreadsheet's export in a decimal-comma locale (or a
// tab-separated one), whose numbers would be misread; named rather than guessed.
void check_separator(std::string_view header, const std::string& source, int line_number) {
  if (header.find(',') != std::string_view::npos) return;
  for (const auto& [separator, name] : {std::pair{';', "semicolons"}, std::pair{'\t', "tabs"}}) {
    const auto count = std::count(header.begin(), header.end(), separator);
    if (count > 0) {
      throw error_at(source, line_number,
                     "header: no comma, but " + std::to_string(count) + " " + name +
                         ": export the table comma-separated, with decimal points");
    }
  }
}

// A cell as CSV text: quoted (RFC 4180) where it holds a comma or a quote, or starts or ends with a space, which the
// reader would otherwise split or trim; as it is otherwise.
std::string quoted_if_needed(const std::string& cell) {
  const bool plain = cell.find_first_of(",\"\n\r") == std::string::npos && trim(cell).size() == cell.size();
  if (plain) return cell;
  std::string quoted = "\"";
  for (char c : cell) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

}  // namespace

CsvTable CsvTable::Parse(const std::string& text, const std::string& source) {
  CsvTable table;
  table.source_ = source;
  std::size_t position = 0;
  int line_number = 0;
  bool have_header = false;
  if (text.starts_with("\xEF\xBB\xBF")) position = 3;  // a UTF-8 byte order mark (a spreadsheet's "CSV UTF-8")
  while (position < text.size()) {
    const auto end = text.find('\n', position);
    const std::string_view line =
        std::string_view(text).substr(position, end == std::string::npos ? std::string::npos : end - position);
    position = end == std::string::npos ? text.size() : end + 1;
    ++line_number;
    const std::string_view content = trim(line);
    if (content.empty() || content.front() == '#') continue;
    if (!have_header) check_separator(content, source, line_number);
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
  for (std::size_t i = 0; i < cells.size(); ++i) file_ << (i ? "," : "") << quoted_if_needed(cells[i]);
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
