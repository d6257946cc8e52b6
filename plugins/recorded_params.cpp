#include "plugins/recorded_params.h"

#include <tuple>

#include "core/error.h"
#include "core/params.h"
#include "generators/generator.h"
#include "plugins/tracer_registry.h"

namespace raycoh {

namespace {

template <class Info>
const ParamTable* table_of(const std::vector<Info>& infos, const std::string& name) {
  for (const Info& info : infos)
    if (info.name == name) return &info.table();
  return nullptr;
}

bool has_row(const ParamTable& table, const std::string& key, ParamType type) {
  for (const ParamSpec& s : table)
    if (s.name == key && s.type == type) return true;
  return false;
}

}  // namespace

RecordedGenerator recorded_generator(const std::string& generator, const std::string& params) {
  // `tile` is the old name of `contiguous`; the primary pass is written in noopt's order.
  const std::string name = generator == "tile" ? "contiguous" : generator == "primary" ? "noopt" : generator;
  const ParamTable* table = table_of(generator_infos(), name);
  RecordedGenerator g;
  if (!table) return g;
  ParamSet set("generator '" + name + "'", params, *table);
  if (has_row(*table, "tile", ParamType::Size)) std::tie(g.tile_w, g.tile_h) = set.get_size("tile");
  if (has_row(*table, "k", ParamType::Int)) g.k = set.get_int("k");
  if (has_row(*table, "order", ParamType::Choice)) g.order = set.get_choice("order");
  return g;
}

RecordedGenerator recorded_generator(const std::string& name, const Generator& generator) {
  if (std::optional<BatchLayout> layout = generator.layout()) return *layout;
  return recorded_generator(name, generator.params());
}

RecordedTracer recorded_tracer(const std::string& tracer, const std::string& params) {
  const ParamTable* table = table_of(tracer_infos(), tracer);
  RecordedTracer t;
  if (!table) return t;
  ParamSet set("tracer '" + tracer + "'", params, *table);
  if (has_row(*table, "preset", ParamType::Choice)) t.preset = set.get_choice("preset");
  if (has_row(*table, "mode", ParamType::Choice)) t.mode = set.get_choice("mode");
  return t;
}

}  // namespace raycoh
