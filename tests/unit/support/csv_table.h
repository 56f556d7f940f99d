// A tiny reader for the transcribed dissertation tables in tests/data:
// '#' lines are comments, the first other line names the columns, fields
// are separated by commas (no quoting).
#pragma once

#include <map>
#include <string>
#include <vector>

namespace vt::test {

struct CsvTable {
  std::vector<std::map<std::string, std::string>> rows;
  /// Rows whose columns equal every (column, value) in `where`.
  std::vector<std::map<std::string, std::string>> select(
      const std::map<std::string, std::string>& where) const;
};

/// Reads `path`; throws std::runtime_error naming the file on failure.
CsvTable read_csv_table(const std::string& path);

/// std::stod of rows[i].at(column), throwing with the column's name.
double number(const std::map<std::string, std::string>& row, const std::string& column);

}  // namespace vt::test
