// Applying a sorted order to a ray batch (docs/design.md section 3). Two modes, reported with every result:
//   physical  gather every array of the RayBatch into a new batch in the sorted order (timed as "permute"), so
//             the tracer reads rays contiguously;
//   indirect  no copy: the tracer fetches ray order[i] for lane i, paying the scattered reads inside the trace.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/ray_batch.h"

namespace raycoh {

enum class PermuteMode { Physical, Indirect };

const char* to_string(PermuteMode mode);
// "physical" | "indirect"; throws raycoh::Error naming the valid choices.
PermuteMode parse_permute_mode(const std::string& text);
std::vector<std::string> permute_mode_names();

// out = in in the given order: element i of every array of out is element order[i] of the same array of in
// (arrays left empty in `in` stay empty); width, height and frame are copied. Parallel gather with oneTBB.
// order must be a permutation of [0, in.size()) (see is_index_permutation).
void permute_batch(const RayBatch& in, const std::vector<uint32_t>& order, RayBatch& out);

// True when order holds each of 0 .. n-1 exactly once.
bool is_index_permutation(const std::vector<uint32_t>& order, size_t n);

}  // namespace raycoh
