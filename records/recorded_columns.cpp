#include "records/recorded_columns.h"

#include <fmt/format.h>

#include "plugins/recorded_params.h"

namespace raycoh {

RecordedColumns recorded_columns(const std::string& generator, const std::string& generator_params,
                                 const std::string& tracer, const std::string& tracer_params) {
  const RecordedGenerator g = recorded_generator(generator, generator_params);
  const RecordedTracer t = recorded_tracer(tracer, tracer_params);
  return {g.tile_w, g.tile_h, g.k, g.order, t.preset, t.mode};
}

RecordedColumns recorded_columns(const std::string& generator_name, const Generator& generator,
                                 const std::string& tracer, const std::string& tracer_params) {
  const RecordedGenerator g = recorded_generator(generator_name, generator);
  const RecordedTracer t = recorded_tracer(tracer, tracer_params);
  return {g.tile_w, g.tile_h, g.k, g.order, t.preset, t.mode};
}

const Schema<RecordedColumns>& recorded_schema() {
  using namespace csv_format;
  using R = RecordedColumns;
  static const Schema<R> schema = {
      column("tile_w", &R::tile_w, Optional<Integer<int>>{}),
      column("tile_h", &R::tile_h, Optional<Integer<int>>{}),
      column("k", &R::k, Optional<Integer<int>>{}),
      column("order", &R::order, Text{}),
      column("preset", &R::preset, Text{}),
      column("mode", &R::mode, Text{}),
  };
  return schema;
}

std::string sweep_method_label(const std::string& generator, int tile_w, int tile_h, int k) {
  return fmt::format("{}:tile={}x{},k={}", generator, tile_w, tile_h, k);
}

ResultKey result_key(const std::string& tracer, const std::string& tracer_params, const std::string& bvh,
                     const RecordedColumns& recorded) {
  return {tracer, recorded.preset, recorded.mode, bvh, tracer_params};
}

ResultKey result_key(const std::string& tracer, const std::string& tracer_params, const std::string& bvh) {
  const RecordedTracer t = recorded_tracer(tracer, tracer_params);
  return {tracer, t.preset, t.mode, bvh, tracer_params};
}

}  // namespace raycoh
