#pragma once
// One table of `batch-collect`'s dataset: named 1-D columns of equal length, in the order they were
// first given. Written as an HDF5 group of columns (pandas makes a DataFrame of it in one call) or
// as CSV text.
#include <cstdint>
#include <initializer_list>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

#include "dmgplace/formats/h5_writer.hpp"

namespace dmgplace::tools {

class DatasetTable {
 public:
  using Column =
      std::variant<std::vector<std::string>, std::vector<std::int64_t>, std::vector<double>, std::vector<std::uint8_t>>;

  // One value of the open row. A float column that is new after the first row, or not given in a
  // row, holds NaN there (joints beyond a robot's count); every other column needs every row.
  void add(std::string_view column, std::string value);
  void add(std::string_view column, std::int64_t value);
  void add(std::string_view column, double value);
  void add(std::string_view column, bool value);
  // Columns in the order given, before the first row: an empty table still names its columns.
  template <class T>
  void declare(std::initializer_list<std::string_view> names) {
    for (auto n : names) columns_.emplace_back(std::string(n), std::vector<T>());
  }
  // Closes the open row. A column missing from it is a programming error (std::logic_error).
  void end_row();

  std::size_t rows() const { return rows_; }
  const std::vector<std::pair<std::string, Column>>& columns() const { return columns_; }

 private:
  template <class T>
  void push(std::string_view column, T value);
  std::vector<std::pair<std::string, Column>> columns_;
  std::size_t rows_ = 0;
  std::size_t next_ = 0;  // where the next add() looks first: rows give their columns in one order
};

// The table as group `group` of `w`: strings as fixed-length UTF-8, the rest as numbers.
void write_table(formats::H5Writer& w, const std::string& group, const DatasetTable& t);
// The table as CSV (RFC 4180): a header row, then one line per row; NaN is an empty cell; a field
// with a comma, quote or line break is quoted with its quotes doubled.
std::string csv_text(const DatasetTable& t);

}  // namespace dmgplace::tools
