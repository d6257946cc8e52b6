// The result CSVs read back as the commands wrote them (the report's data access): any raycoh result CSV as columns
// and text rows, its kind from its columns, and the typed recorded parameters of a row — from the typed columns
// (records/recorded_columns.h), or for a file written before them through the plugins' own tables.
#pragma once

#include <cmath>
#include <cstdlib>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "records/recorded_columns.h"

namespace raycoh {

struct ResultCsv {
  std::string path;
  std::vector<std::string> columns;
  std::vector<std::vector<std::string>> rows;
  int col(const std::string& name) const {
    const auto it = std::find(columns.begin(), columns.end(), name);
    return it == columns.end() ? -1 : static_cast<int>(it - columns.begin());
  }
  bool has(const std::string& name) const { return col(name) >= 0; }
  const std::string& get(const std::vector<std::string>& row, const std::string& name) const {
    static const std::string empty;
    const int c = col(name);
    return c < 0 ? empty : row[static_cast<size_t>(c)];
  }
  double num(const std::vector<std::string>& row, const std::string& name) const {
    const std::string& s = get(row, name);
    if (s.empty()) return NAN;
    char* end = nullptr;
    const double v = std::strtod(s.c_str(), &end);
    return end && *end == '\0' ? v : NAN;
  }
};

// Throws raycoh::Error ("report: ...") for a file that cannot be read, unbalanced quotes, a row of another width.
ResultCsv read_result_csv(const std::string& path);

enum class ResultKind { Table, Sweep, Converge, ConvergeSummary, Quality, Validate, Stability, Tune, TuneConfirm };
// From the columns (and for table against sweep, the methods); throws raycoh::Error for a CSV of no known kind.
ResultKind result_kind(const ResultCsv& c);

// A row's tile, K, order, preset and mode (table/sweep, quality and converge CSVs).
RecordedColumns recorded_of(const ResultCsv& c, const std::vector<std::string>& row);
// The key of a row's results (records/result_key.h): tracer, typed preset and mode, bvh, tracer_params.
ResultKey result_key_of(const ResultCsv& c, const std::vector<std::string>& row);

// The tile and K of a sweep cell's row: set when `method` is the sweep's label of that tile and K
// (sweep_method_label), empty otherwise.
struct SweepCell {
  int tile_w = 0, tile_h = 0, k = 0;
};
std::optional<SweepCell> sweep_cell(const std::string& method, const std::string& generator,
                                    const RecordedColumns& recorded);

void add_unique(std::vector<std::string>& v, const std::string& s);
std::string join_set(const std::set<std::string>& s, const char* sep = ", ");

}  // namespace raycoh
