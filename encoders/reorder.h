// One frame's reordering step, with each stage timed (steady_clock): keys (Encoder::encode), sort (stable radix
// sort of key/index pairs over exactly the key's bits) and permute (physical gather; 0 in indirect mode, whose
// cost shows up in the trace). A reordering method only wins if it wins end to end, so the harness reports
// these next to the trace time.
#pragma once

#include <cstdint>
#include <vector>

#include "encoders/encoder.h"
#include "encoders/permute.h"

namespace raycoh {

struct ReorderTimings {
  double key_ms = 0.0;
  double sort_ms = 0.0;
  double permute_ms = 0.0;
  double total_ms() const { return key_ms + sort_ms + permute_ms; }
};

// Reorders `in` with the encoder's keys. Returns false, with order cleared, out untouched and all times 0, when
// the encoder makes no keys (`none`): trace `in` as it is. Otherwise order holds the sorted ray indices (a
// permutation of 0 .. in.size()-1, stable for equal keys) and, in Physical mode, out is `in` in that order; in
// Indirect mode out is untouched and the tracer reads ray order[i] for lane i. The sorted keys stay in
// encoder.workspace().keys (keys[i] belongs to ray order[i]). Buffers are sized before the clocks start, so
// the times are the work of each stage.
bool reorder(Encoder& encoder, const RayBatch& in, PermuteMode mode, RayBatch& out, std::vector<uint32_t>& order,
             ReorderTimings& timings);

}  // namespace raycoh
