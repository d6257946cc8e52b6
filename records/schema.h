// One column table per CSV: for each column its name, how a record's field is written as text and read back, and
// whether it is part of the resume key. The header, every row, the resume of an interrupted run and (through the
// records) the console tables all come from it, so a new column is one line in its table plus its record field.
#pragma once

#include <fmt/format.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace raycoh {

enum class Key { No, Yes };

template <class Row>
struct Column {
  std::string name;
  std::function<std::string(const Row&)> write;
  std::function<void(Row&, const std::string&)> read;  // throws std::invalid_argument on a value it cannot hold
  bool key = false;
};

template <class Row>
using Schema = std::vector<Column<Row>>;

// Field formats. Each is a type with static write(value) and read(text); read rejects anything write cannot make.
namespace csv_format {

[[noreturn]] inline void bad(const std::string& text, const char* what) {
  throw std::invalid_argument(fmt::format("'{}' is not {}", text, what));
}

struct Text {
  static std::string write(const std::string& v) { return v; }
  static std::string read(const std::string& s) { return s; }
};

template <class T>
struct Integer {
  static std::string write(T v) { return std::to_string(v); }
  static T read(const std::string& s) {
    char* end = nullptr;
    errno = 0;
    const auto v = std::is_signed_v<T> ? static_cast<long long>(std::strtoll(s.c_str(), &end, 10))
                                       : static_cast<long long>(std::strtoull(s.c_str(), &end, 10));
    if (s.empty() || *end != '\0' || errno != 0 || (!std::is_signed_v<T> && s[0] == '-')) bad(s, "an integer");
    return static_cast<T>(v);
  }
};

inline double read_double(const std::string& s) {
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (s.empty() || *end != '\0') bad(s, "a number");
  return v;
}

// "{:.Nf}": times in milliseconds, speeds.
template <int N>
struct Fixed {
  static std::string write(double v) { return fmt::format("{:.{}f}", v, N); }
  static double read(const std::string& s) { return read_double(s); }
};

// "{:.6g}".
struct General {
  static std::string write(double v) { return fmt::format("{:.6g}", v); }
  static double read(const std::string& s) { return read_double(s); }
};

// "{:.6g}", NaN (not measured, undefined) as an empty field.
struct GeneralOrEmpty {
  static std::string write(double v) { return std::isnan(v) ? std::string() : General::write(v); }
  static double read(const std::string& s) { return s.empty() ? std::nan("") : read_double(s); }
};

// Numbers separated by ';' ("{:.6g}" each, NaN as an empty item): one value per render, in render order.
struct Numbers {
  static std::string write(const std::vector<double>& v) {
    std::string out;
    for (size_t i = 0; i < v.size(); ++i) out += (i ? ";" : "") + GeneralOrEmpty::write(v[i]);
    return out;
  }
  static std::vector<double> read(const std::string& s) {
    std::vector<double> out;
    if (s.empty()) return out;
    for (size_t at = 0;;) {
      const size_t end = s.find(';', at);
      out.push_back(GeneralOrEmpty::read(s.substr(at, end == std::string::npos ? std::string::npos : end - at)));
      if (end == std::string::npos) return out;
      at = end + 1;
    }
  }
};

// An optional value: empty when absent (e.g. generation counts of the primary pass).
template <class F>
struct Optional {
  template <class T>
  static std::string write(const std::optional<T>& v) {
    return v ? F::write(*v) : std::string();
  }
  static auto read(const std::string& s) -> std::optional<decltype(F::read(s))> {
    if (s.empty()) return std::nullopt;
    return F::read(s);
  }
};

}  // namespace csv_format

// A column bound to a field of Row.
template <class Row, class T, class F>
Column<Row> column(std::string name, T Row::*field, F, Key key = Key::No) {
  return {std::move(name), [field](const Row& r) { return F::write(r.*field); },
          [field](Row& r, const std::string& s) { r.*field = F::read(s); }, key == Key::Yes};
}

// The columns of a nested record (e.g. Provenance inside every row), appended after `out`'s own.
template <class Row, class Sub>
void append_columns(Schema<Row>& out, const Schema<Sub>& sub, Sub Row::*member) {
  for (const Column<Sub>& c : sub)
    out.push_back({c.name, [member, w = c.write](const Row& r) { return w(r.*member); },
                   [member, rd = c.read](Row& r, const std::string& s) { rd(r.*member, s); }, c.key});
}

template <class Row>
std::vector<std::string> column_names(const Schema<Row>& schema) {
  std::vector<std::string> names;
  for (const Column<Row>& c : schema) names.push_back(c.name);
  return names;
}

template <class Row>
std::vector<std::string> write_row(const Schema<Row>& schema, const Row& row) {
  std::vector<std::string> fields;
  for (const Column<Row>& c : schema) fields.push_back(c.write(row));
  return fields;
}

// Reads a row written with this schema; std::invalid_argument names the column and the value.
template <class Row>
Row read_row(const Schema<Row>& schema, const std::vector<std::string>& fields) {
  if (fields.size() != schema.size())
    throw std::invalid_argument(fmt::format("{} fields for {} columns", fields.size(), schema.size()));
  Row row;
  for (size_t i = 0; i < schema.size(); ++i) {
    try {
      schema[i].read(row, fields[i]);
    } catch (const std::exception& e) {
      throw std::invalid_argument(fmt::format("column {}: {}", schema[i].name, e.what()));
    }
  }
  return row;
}

// The resume key: the key columns' text, joined with a separator no field contains.
template <class Row>
std::string resume_key(const Schema<Row>& schema, const Row& row) {
  std::string k;
  for (const Column<Row>& c : schema)
    if (c.key) k += c.write(row) + '\x1f';
  return k;
}

}  // namespace raycoh
