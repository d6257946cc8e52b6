// The recorded parameters a reader needs, as typed columns of every CSV whose rows name a generator or a tracer
// (table/sweep, quality, converge): the generator's tile, group size K and batch order, the tracer's GPU preset
// (simt) and Embree call mode (embree). They are the last columns, after the provenance, so that the columns
// before them keep their places; a row fills them from its generator_params and tracer_params through the plugins'
// own tables (plugins/recorded_params.h), and a reader of an older CSV (the report) fills them the same way. No
// reader parses parameter text itself.
#pragma once

#include <optional>
#include <string>

#include "records/result_key.h"
#include "records/schema.h"

namespace raycoh {

class Generator;

struct RecordedColumns {
  std::optional<int> tile_w, tile_h, k;  // empty where the generator has no such parameter (and for noopt's K)
  std::string order;                     // batch order: scanline | tile | group; empty where it has none
  std::string preset, mode;              // simt's GPU preset, embree's call mode; empty for other tracers
};

RecordedColumns recorded_columns(const std::string& generator, const std::string& generator_params,
                                 const std::string& tracer, const std::string& tracer_params);
// The same, for a generator that ran (its typed layout where it gives one: plugins/recorded_params.h).
RecordedColumns recorded_columns(const std::string& generator_name, const Generator& generator,
                                 const std::string& tracer, const std::string& tracer_params);

// tile_w, tile_h, k, order, preset, mode.
const Schema<RecordedColumns>& recorded_schema();

// The method label of one sweep cell ("ours:tile=8x8,k=16"): `raycoh sweep` names its methods so, and a reader
// knows a sweep's cells by it (with the typed tile and K of their rows).
std::string sweep_method_label(const std::string& generator, int tile_w, int tile_h, int k);

// The key of the results of a tracer (records/result_key.h): its name, typed preset and mode (the recorded
// columns), acceleration structure and canonical parameters.
ResultKey result_key(const std::string& tracer, const std::string& tracer_params, const std::string& bvh,
                     const RecordedColumns& recorded);
// The same for a tracer that runs, its preset and mode read through its own table (plugins/recorded_params.h).
ResultKey result_key(const std::string& tracer, const std::string& tracer_params, const std::string& bvh);

}  // namespace raycoh
