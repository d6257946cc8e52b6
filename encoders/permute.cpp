// Physical reordering of a ray batch and the permutation check (see permute.h).
#include "encoders/permute.h"

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "core/error.h"
#include "core/params.h"

namespace raycoh {
namespace {

// Resizes out to n when in holds n elements (the array is gathered), or clears it when in's array is empty.
template <class T>
bool prepare(const std::vector<T>& in, std::vector<T>& out, size_t n, const char* name) {
  RAYCOH_CHECK(in.empty() || in.size() == n,
               fmt::format("RayBatch::{} has {} elements for {} rays", name, in.size(), n));
  out.resize(in.empty() ? 0 : n);
  return !in.empty();
}

}  // namespace

const char* to_string(PermuteMode mode) { return mode == PermuteMode::Physical ? "physical" : "indirect"; }

std::vector<std::string> permute_mode_names() { return {"physical", "indirect"}; }

PermuteMode parse_permute_mode(const std::string& text) {
  if (text == "physical") return PermuteMode::Physical;
  if (text == "indirect") return PermuteMode::Indirect;
  throw Error(fmt::format("unknown permutation mode '{}'; valid modes: {}", text, join(permute_mode_names())));
}

void permute_batch(const RayBatch& in, const std::vector<uint32_t>& order, RayBatch& out) {
  const size_t n = in.size();
  RAYCOH_CHECK(order.size() == n, fmt::format("order has {} indices for {} rays", order.size(), n));
  RAYCOH_CHECK(&in != &out, std::string("permute_batch cannot work in place"));
  out.width = in.width;
  out.height = in.height;
  out.frame = in.frame;
#define RAYCOH_PREPARE(name, T, grouped) const bool has_##name = prepare(in.name, out.name, n, #name);
  RAYCOH_BATCH_COLUMNS(RAYCOH_PREPARE)
#undef RAYCOH_PREPARE
  RAYCOH_CHECK(has_rays || n == 0, std::string("permute_batch: the batch has no rays"));
  // One pass gathers all columns, so each index is read once.
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 4096), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i < r.end(); ++i) {
      const uint32_t j = order[i];
#define RAYCOH_GATHER(name, T, grouped) \
  if (has_##name) out.name[i] = in.name[j];
      RAYCOH_BATCH_COLUMNS(RAYCOH_GATHER)
#undef RAYCOH_GATHER
    }
  });
}

bool is_index_permutation(const std::vector<uint32_t>& order, size_t n) {
  if (order.size() != n) return false;
  std::vector<bool> seen(n, false);
  for (uint32_t i : order) {
    if (i >= n || seen[i]) return false;
    seen[i] = true;
  }
  return true;
}

}  // namespace raycoh
