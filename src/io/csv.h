#pragma once
// Comma-separated tables with a header row: the reference torque profiles, the trial logs and the files users
// import. Reading is strict: every row has the header's number of cells, and every error names the file, the line
// and the column, so a bad row from another lab's spreadsheet is found, not silently skipped.

#include <cstddef>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

namespace softwrist::io {

class CsvTable {
 public:
  // Parses `text`. A UTF-8 byte order mark is skipped, and so are blank lines and lines starting with '#'; cells are
  // trimmed; a quoted cell (RFC 4180, '""' for a quote) must end on its line. A header that semicolons or tabs
  // separate instead of commas is refused, named. Throws std::runtime_error("<source>:<line>: <problem>").
  static CsvTable Parse(const std::string& text, const std::string& source);
  static CsvTable Read(const std::filesystem::path& path);

  const std::string& source() const { return source_; }
  const std::vector<std::string>& header() const { return header_; }
  std::size_t row_count() const { return rows_.size(); }
  int line_of(std::size_t row) const { return lines_[row]; }

  // Index of the named column, or -1.
  int find_column(std::string_view name) const;
  // Index of the named column; throws "<source>: missing column '<name>' (columns: ...)".
  int column(std::string_view name) const;
  const std::string& cell(std::size_t row, int column) const { return rows_[row][column]; }
  // The cell as a finite number; throws "<source>:<line>: <column>: <problem>: '<cell>'".
  double number(std::size_t row, int column) const;
  // The cell as a whole number that fits an int (a case index, a count); throws as number() does.
  int integer(std::size_t row, int column) const;
  // These columns, in this order, under new names: the same source, rows and line numbers (for messages).
  CsvTable select(const std::vector<int>& columns, std::vector<std::string> names) const;

 private:
  std::string source_;
  std::vector<std::string> header_;
  std::vector<std::vector<std::string>> rows_;
  std::vector<int> lines_;
};

// Writes a CSV row by row (a cell with a comma, a quote or an outer space quoted, as the reader reads it), flushing
// each row so that a killed process leaves every written row readable.
class CsvWriter {
 public:
  // Creates (or truncates) `path` and writes the header row.
  CsvWriter(const std::filesystem::path& path, std::vector<std::string> header);
  // Appends to `path`, whose complete rows have `header`'s columns (a resumed run): writes no header.
  struct Append {};
  CsvWriter(const std::filesystem::path& path, std::vector<std::string> header, Append);
  void write_row(const std::vector<std::string>& cells);
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
  std::size_t columns_;
  std::ofstream file_;
};

// Shortest text that reads back to the same double (std::to_chars), for data files.
std::string format_number(double value);

}  // namespace softwrist::io
