// The parameters a reader of results needs, as typed values: read from a plugin's canonical parameter text (the
// generator_params / tracer_params a row records) through that plugin's own parameter table. This is the one
// reader of recorded parameter text: the results layer (records/) calls it when it fills a row's typed columns
// (tile, k, order, preset, mode) and when it reads a CSV written before those columns existed; no other reader
// parses parameter text.
#pragma once

#include <optional>
#include <string>

#include "generators/generator.h"

namespace raycoh {

// What decides a generator's batch layout. Empty where the generator has no such parameter (direct has a tile
// but no K or order; shared-sample generators no K), and all empty for a name no registry knows. The primary
// pass ("primary") is read as noopt: camera rays are written in noopt's order.
using RecordedGenerator = BatchLayout;
RecordedGenerator recorded_generator(const std::string& generator, const std::string& params);
// The same of a generator that ran: its typed layout (Generator::layout()) where it gives one, else its canonical
// params() read as above. `name` is the generator's registry name.
RecordedGenerator recorded_generator(const std::string& name, const Generator& generator);

// What tells tracers of one name apart in a figure: the GPU model's preset (simt) and Embree's call mode (embree);
// empty for tracers without them.
struct RecordedTracer {
  std::string preset, mode;
};
RecordedTracer recorded_tracer(const std::string& tracer, const std::string& params);

}  // namespace raycoh
