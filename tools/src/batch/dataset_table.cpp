#include "dataset_table.hpp"

#include <charconv>
#include <cmath>
#include <limits>
#include <span>
#include <stdexcept>
#include <type_traits>

namespace dmgplace::tools {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::size_t size_of(const DatasetTable::Column& c) {
  return std::visit([](const auto& v) { return v.size(); }, c);
}

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\r\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

// The shortest text that reads back as the same double; NaN is an empty cell.
std::string csv_number(double v) {
  if (std::isnan(v)) return "";
  char b[32];
  const auto r = std::to_chars(b, b + sizeof b, v);
  return std::string(b, r.ptr);
}

std::string csv_cell(const DatasetTable::Column& c, std::size_t row) {
  struct Cell {
    std::size_t row;
    std::string operator()(const std::vector<std::string>& v) const { return csv_field(v[row]); }
    std::string operator()(const std::vector<std::int64_t>& v) const { return std::to_string(v[row]); }
    std::string operator()(const std::vector<double>& v) const { return csv_number(v[row]); }
    std::string operator()(const std::vector<std::uint8_t>& v) const { return std::to_string(int(v[row])); }
  };
  return std::visit(Cell{row}, c);
}

}  // namespace

template <class T>
void DatasetTable::push(std::string_view column, T value) {
  if (next_ >= columns_.size() || columns_[next_].first != column) {
    next_ = 0;
    while (next_ < columns_.size() && columns_[next_].first != column) ++next_;
  }
  if (next_ == columns_.size()) {
    if constexpr (std::is_same_v<T, double>)
      columns_.emplace_back(std::string(column), std::vector<double>(rows_, kNaN));
    else if (rows_ > 0)
      throw std::logic_error("dataset column " + std::string(column) + " appears after the first row");
    else columns_.emplace_back(std::string(column), std::vector<T>());
  }
  auto* values = std::get_if<std::vector<T>>(&columns_[next_].second);
  if (!values) throw std::logic_error("dataset column " + std::string(column) + " given values of two types");
  if (values->size() != rows_)
    throw std::logic_error("dataset column " + std::string(column) + " given twice in a row");
  values->push_back(std::move(value));
  ++next_;
}

void DatasetTable::add(std::string_view column, std::string value) { push(column, std::move(value)); }
void DatasetTable::add(std::string_view column, std::int64_t value) { push(column, value); }
void DatasetTable::add(std::string_view column, double value) { push(column, value); }
void DatasetTable::add(std::string_view column, bool value) { push(column, std::uint8_t(value)); }

void DatasetTable::end_row() {
  for (auto& [name, column] : columns_) {
    if (size_of(column) == rows_ + 1) continue;
    auto* floats = std::get_if<std::vector<double>>(&column);
    if (!floats) throw std::logic_error("dataset column " + name + " missing from row " + std::to_string(rows_));
    floats->push_back(kNaN);
  }
  ++rows_;
  next_ = 0;
}

void write_table(formats::H5Writer& w, const std::string& group, const DatasetTable& t) {
  w.ordered_group(group);
  for (const auto& [name, column] : t.columns()) {
    const std::string path = group + "/" + name;
    if (const auto* s = std::get_if<std::vector<std::string>>(&column)) {
      w.write_utf8_strings(path, *s);
      continue;
    }
    std::visit(
        [&](const auto& v) {
          using T = typename std::decay_t<decltype(v)>::value_type;
          if constexpr (!std::is_same_v<T, std::string>) w.write(path, std::span<const T>(v), {v.size()});
        },
        column);
  }
}

std::string csv_text(const DatasetTable& t) {
  std::string text;
  for (std::size_t c = 0; c < t.columns().size(); ++c) text += (c ? "," : "") + csv_field(t.columns()[c].first);
  text += "\r\n";
  for (std::size_t row = 0; row < t.rows(); ++row) {
    for (std::size_t c = 0; c < t.columns().size(); ++c) text += (c ? "," : "") + csv_cell(t.columns()[c].second, row);
    text += "\r\n";
  }
  return text;
}

}  // namespace dmgplace::tools
