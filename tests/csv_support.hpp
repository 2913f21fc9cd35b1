// Reference traces for the model tests (test_afc, test_nn, test_sc): a numeric CSV with a header
// row, read into columns by name. Rows whose cell count differs from the header's are skipped
// (a trailing blank line, a truncated last row).
#pragma once
#include <gtest/gtest.h>

#include <cstddef>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace hyfal_csv_test {

struct CsvColumns {
  std::vector<std::string> header;
  std::vector<std::vector<double>> columns;  // [column][row]

  std::size_t rows() const { return columns.empty() ? 0 : columns[0].size(); }
  const std::vector<double>& operator[](const std::string& name) const {
    for (std::size_t i = 0; i < header.size(); ++i)
      if (header[i] == name) return columns[i];
    throw std::out_of_range("no column '" + name + "'");
  }
};

inline std::vector<std::string> split_csv_line(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream ss(line);
  for (std::string cell; std::getline(ss, cell, ',');) cells.push_back(cell);
  return cells;
}

// `expected_header`: the header row as the file must have it (a test of the data's layout).
inline CsvColumns read_csv_columns(const std::string& path, const std::string& expected_header) {
  std::ifstream in(path);
  EXPECT_TRUE(in) << path;
  CsvColumns t;
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, expected_header) << path;
  t.header = split_csv_line(line);
  t.columns.resize(t.header.size());
  while (std::getline(in, line)) {
    const std::vector<std::string> cells = split_csv_line(line);
    if (cells.size() != t.header.size()) continue;
    for (std::size_t i = 0; i < cells.size(); ++i) t.columns[i].push_back(std::stod(cells[i]));
  }
  return t;
}

}  // namespace hyfal_csv_test
