#include "records/result_csv.h"

#include <fmt/format.h>

#include <algorithm>
#include <fstream>

#include "core/error.h"
#include "generators/generator.h"
#include "records/csv.h"

namespace raycoh {

ResultCsv read_result_csv(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(fmt::format("report: cannot read {}", path));
  ResultCsv csv;
  csv.path = path;
  std::string line;
  int number = 0;
  std::vector<std::string> fields;
  while (std::getline(in, line)) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || line[0] == '#') continue;
    if (!csv_parse_line(line, fields)) throw Error(fmt::format("report: {} line {}: unbalanced quotes", path, number));
    if (csv.columns.empty()) {
      csv.columns = fields;
      continue;
    }
    if (fields.size() != csv.columns.size())
      throw Error(fmt::format("report: {} line {}: {} fields, the header has {}", path, number, fields.size(),
                              csv.columns.size()));
    csv.rows.push_back(fields);
  }
  if (csv.columns.empty()) throw Error(fmt::format("report: {}: empty file, no CSV header", path));
  return csv;
}

ResultKind result_kind(const ResultCsv& c) {
  if (c.has("pass") && c.has("method") && c.has("mray_s")) {
    size_t cells = 0, others = 0;  // a sweep: its every method but noopt a tile x K cell of ours or contiguous
    for (const auto& r : c.rows) {
      if (c.get(r, "pass") != "secondary" || c.get(r, "method") == "noopt") continue;
      const std::string& g = c.get(r, "generator");
      const bool grouping = group_size_row(g) != nullptr;
      ++(grouping && sweep_cell(c.get(r, "method"), g, recorded_of(c, r)) ? cells : others);
    }
    return cells > 0 && others == 0 ? ResultKind::Sweep : ResultKind::Table;
  }
  if (c.has("equal_time_error_ratio")) return ResultKind::ConvergeSummary;
  if (c.has("rel_mse") && c.has("wall_s") && c.has("frame")) return ResultKind::Converge;
  if (c.has("psnr") && c.has("reference_kind")) return ResultKind::Quality;
  if (c.has("paper_ratio") && c.has("modeled_ratio")) return ResultKind::Validate;
  if (c.has("case") && c.has("rate") && c.has("threshold") && c.has("status")) return ResultKind::Stability;
  if (c.has("meets_budget") && c.has("setting")) return ResultKind::Tune;
  if (c.has("held") && c.has("claim") && c.has("baseline")) return ResultKind::TuneConfirm;
  throw Error(fmt::format(
      "report: {}: not a raycoh result CSV; valid: the CSVs of table, sweep, converge (curve or -summary), quality, "
      "validate, stability, tune and tune --confirm (results/README.md)",
      c.path));
}

RecordedColumns recorded_of(const ResultCsv& c, const std::vector<std::string>& row) {
  if (!c.has("tile_w"))  // written before the typed columns: read through the plugins' tables
    return recorded_columns(c.get(row, "generator"), c.get(row, "generator_params"), c.get(row, "tracer"),
                            c.get(row, "tracer_params"));
  RecordedColumns r;
  const Schema<RecordedColumns>& schema = recorded_schema();
  for (const Column<RecordedColumns>& col : schema) col.read(r, c.get(row, col.name));
  return r;
}

ResultKey result_key_of(const ResultCsv& c, const std::vector<std::string>& row) {
  return result_key(c.get(row, "tracer"), c.get(row, "tracer_params"), c.get(row, "bvh"), recorded_of(c, row));
}

std::optional<SweepCell> sweep_cell(const std::string& method, const std::string& generator,
                                    const RecordedColumns& recorded) {
  if (!recorded.tile_w || !recorded.tile_h || !recorded.k) return std::nullopt;
  if (method != sweep_method_label(generator, *recorded.tile_w, *recorded.tile_h, *recorded.k)) return std::nullopt;
  return SweepCell{*recorded.tile_w, *recorded.tile_h, *recorded.k};
}

void add_unique(std::vector<std::string>& v, const std::string& s) {
  if (std::find(v.begin(), v.end(), s) == v.end()) v.push_back(s);
}

std::string join_set(const std::set<std::string>& s, const char* sep) {
  std::string out;
  for (const std::string& v : s) out += (out.empty() ? "" : sep) + v;
  return out;
}

// The footer of a figure: resolution, frames and revision, then the tracers (two lines of SVG text).

}  // namespace raycoh
