// Strict CSV reading: every problem is reported with the file, the line and the column.

#include "io/csv.h"

#include <unistd.h>
#include <cmath>
#include <filesystem>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

namespace softwrist::io {
namespace {

using ::testing::HasSubstr;

std::string error_of(const std::string& text, const std::string& column = "torque_nm") {
  try {
    const CsvTable table = CsvTable::Parse(text, "ref.csv");
    const int c = table.column(column);
    for (std::size_t row = 0; row < table.row_count(); ++row) (void)table.number(row, c);
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

TEST(CsvTable, ReadsNumbersSkippingCommentsAndBlankLines) {
  const CsvTable table = CsvTable::Parse("# comment\nangle_deg, torque_nm\n\n-67.5, 3.75\n+0,1e-1\n", "ref.csv");
  ASSERT_EQ(table.row_count(), 2u);
  EXPECT_EQ(table.column("torque_nm"), 1);
  EXPECT_EQ(table.number(0, 0), -67.5);
  EXPECT_EQ(table.number(1, 1), 0.1);
  EXPECT_EQ(table.line_of(1), 5);
  EXPECT_EQ(table.find_column("pressure_kpa"), -1);
}

TEST(CsvTable, BadInputIsNamedByFileLineAndColumn) {
  EXPECT_THAT(error_of("angle_deg,torque_nm\n1,2\n3,abc\n"), HasSubstr("ref.csv:3: torque_nm: not a number: 'abc'"));
  EXPECT_THAT(error_of("angle_deg,torque_nm\n1,nan\n"), HasSubstr("ref.csv:2: torque_nm: not a finite number"));
  EXPECT_THAT(error_of("angle_deg,torque_nm\n1,inf\n"), HasSubstr("ref.csv:2: torque_nm: not a finite number"));
  EXPECT_THAT(error_of("angle_deg,torque_nm\n1,\n"), HasSubstr("ref.csv:2: torque_nm: empty cell"));
  EXPECT_THAT(error_of("angle_deg,torque_nm\n1,2,3\n"), HasSubstr("ref.csv:2: expected 2 cells, found 3"));
  EXPECT_THAT(error_of("angle_deg,torque\n1,2\n"),
              HasSubstr("ref.csv: missing column 'torque_nm' (columns: angle_deg, torque)"));
  EXPECT_THAT(error_of("angle_deg,angle_deg\n"), HasSubstr("appears twice"));
  EXPECT_THAT(error_of("angle_deg,\"torque_nm\n"), HasSubstr("ref.csv:1: a quoted cell does not end on its line"));
  EXPECT_THAT(error_of("angle_deg,\"torque\"_nm\n"), HasSubstr("ref.csv:1: text after a quoted cell's closing quote"));
  EXPECT_THAT(error_of("angle_deg,torque_nm\n1,2\"\n"), HasSubstr("ref.csv:2: a quote inside an unquoted cell: '2\"'"));
  EXPECT_THAT(error_of(""), HasSubstr("ref.csv: empty file"));
  EXPECT_THAT(error_of("angle_deg,torque_nm\n1,2x\n"), HasSubstr("not a number"));
}

// What spreadsheets export: a byte order mark ("CSV UTF-8"), CRLF line ends, quoted text cells; and in a
// decimal-comma locale semicolons, which are refused by name rather than misread.
TEST(CsvTable, ReadsSpreadsheetExportsAndNamesSemicolonsAndTabs) {
  const CsvTable table = CsvTable::Parse(
      "\xEF\xBB\xBF\"angle_deg\",\"case\"\r\n-1.5, \"steps, \"\"slow\"\"\" \r\n2,\"\"\r\n", "export.csv");
  ASSERT_EQ(table.row_count(), 2u);
  EXPECT_EQ(table.column("angle_deg"), 0);
  EXPECT_EQ(table.number(0, 0), -1.5);
  EXPECT_EQ(table.cell(0, 1), "steps, \"slow\"");
  EXPECT_EQ(table.cell(1, 1), "");
  EXPECT_THAT(error_of("angle_deg;torque_nm\n1,5;2\n"),
              HasSubstr("ref.csv:1: header: no comma, but 1 semicolons: export the table comma-separated"));
  EXPECT_THAT(error_of("# rig 2\nangle_deg\ttorque_nm\n"), HasSubstr("ref.csv:2: header: no comma, but 1 tabs"));
  EXPECT_EQ(error_of("torque_nm\n1\n"), "");  // one column needs no separator
}

// Counts and case indices: whole numbers within int's range, checked before any cast (a count of 2e20 was cast to
// int, undefined behaviour, until the csv_import fuzzer found it).
TEST(CsvTable, IntegerCellsAreWholeAndWithinIntsRange) {
  const CsvTable table = CsvTable::Parse("n\n3\n-2\n2147483647\n2147483648\n1.5\n2e20\n", "counts.csv");
  EXPECT_EQ(table.integer(0, 0), 3);
  EXPECT_EQ(table.integer(1, 0), -2);
  EXPECT_EQ(table.integer(2, 0), 2147483647);
  for (std::size_t row : {3u, 4u, 5u}) {
    EXPECT_THAT([&] { (void)table.integer(row, 0); },
                ::testing::ThrowsMessage<std::runtime_error>(
                    HasSubstr("counts.csv:" + std::to_string(row + 2) + ": n: not a whole number in int's range")));
  }
}

TEST(CsvWriter, RoundTripsNumbersExactlyAndTextCells) {
  const auto path =
      std::filesystem::temp_directory_path() / ("softwrist_csv_test_" + std::to_string(::getpid()) + ".csv");
  {
    CsvWriter writer(path, {"a", "b"});
    writer.write_row({format_number(0.1), format_number(-1.0 / 3.0)});
    writer.write_row({"steps, \"slow\"", " padded "});  // text cells come back as they went in
  }
  const CsvTable table = CsvTable::Read(path);
  EXPECT_EQ(table.number(0, 0), 0.1);
  EXPECT_EQ(table.number(0, 1), -1.0 / 3.0);
  EXPECT_EQ(table.cell(1, 0), "steps, \"slow\"");
  EXPECT_EQ(table.cell(1, 1), " padded ");
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace softwrist::io
