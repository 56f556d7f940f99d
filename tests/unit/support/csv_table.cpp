#include "support/csv_table.h"

#include <fstream>
#include <sstream>
#include <stdexcept>

namespace vt::test {
namespace {
std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream ss(line);
  std::string cell;
  while (std::getline(ss, cell, ',')) out.push_back(cell);
  if (!line.empty() && line.back() == ',') out.emplace_back();
  return out;
}
}  // namespace

CsvTable read_csv_table(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open");
  CsvTable t;
  std::vector<std::string> header;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    if (header.empty()) {
      header = split(line);
      continue;
    }
    const auto cells = split(line);
    if (cells.size() != header.size())
      throw std::runtime_error(path + ": a row has " + std::to_string(cells.size()) +
                               " fields, the header " + std::to_string(header.size()));
    std::map<std::string, std::string> row;
    for (std::size_t i = 0; i < header.size(); ++i) row[header[i]] = cells[i];
    t.rows.push_back(row);
  }
  return t;
}

std::vector<std::map<std::string, std::string>> CsvTable::select(
    const std::map<std::string, std::string>& where) const {
  std::vector<std::map<std::string, std::string>> out;
  for (const auto& r : rows) {
    bool ok = true;
    for (const auto& [k, v] : where)
      if (r.at(k) != v) ok = false;
    if (ok) out.push_back(r);
  }
  return out;
}

double number(const std::map<std::string, std::string>& row, const std::string& column) {
  const auto it = row.find(column);
  if (it == row.end() || it->second.empty())
    throw std::runtime_error("csv: no value in column " + column);
  return std::stod(it->second);
}

}  // namespace vt::test
