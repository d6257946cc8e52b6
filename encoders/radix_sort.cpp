// Stable parallel LSD radix sort (see radix_sort.h for the method and parameters).
#include "encoders/radix_sort.h"

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <limits>
#include <utility>

#include "core/error.h"

namespace raycoh {
namespace {

// Blocks are the unit of parallel work. A few per thread balance the load; below this size the per-block
// histogram and scan would cost more than the pass.
constexpr size_t kMinBlock = 1 << 15;
constexpr size_t kBlocksPerThread = 4;

}  // namespace

void RadixSortScratch::reserve(size_t n) {
  if (keys.size() < n) keys.resize(n);
  if (values.size() < n) values.resize(n);
}

void radix_sort_pairs(std::vector<uint64_t>& keys, std::vector<uint32_t>& values, int key_bits,
                      RadixSortScratch& scratch, int digit_bits) {
  RAYCOH_CHECK(keys.size() == values.size(), fmt::format("{} keys, {} values", keys.size(), values.size()));
  RAYCOH_CHECK(key_bits >= 0 && key_bits <= 64, fmt::format("key_bits = {}", key_bits));
  RAYCOH_CHECK(digit_bits >= 1 && digit_bits <= 16, fmt::format("digit_bits = {}", digit_bits));
  const size_t n = keys.size();
  RAYCOH_CHECK(n <= std::numeric_limits<uint32_t>::max(), fmt::format("{} pairs", n));
  if (n < 2 || key_bits == 0) return;

  scratch.reserve(n);
  const size_t threads = static_cast<size_t>(std::max(1, tbb::this_task_arena::max_concurrency()));
  const size_t block_count = std::clamp<size_t>(n / kMinBlock, 1, kBlocksPerThread * threads);
  const size_t block_size = (n + block_count - 1) / block_count;
  const size_t radix = size_t{1} << digit_bits;
  if (scratch.counts.size() < block_count * radix) scratch.counts.resize(block_count * radix);

  uint64_t* src_keys = keys.data();
  uint32_t* src_values = values.data();
  uint64_t* dst_keys = scratch.keys.data();
  uint32_t* dst_values = scratch.values.data();
  uint32_t* counts = scratch.counts.data();
  bool result_in_scratch = false;

  for (int shift = 0; shift < key_bits; shift += digit_bits) {
    const int width = std::min(digit_bits, key_bits - shift);
    const size_t digits = size_t{1} << width;
    const uint64_t mask = digits - 1;

    tbb::parallel_for(tbb::blocked_range<size_t>(0, block_count, 1), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t b = r.begin(); b < r.end(); ++b) {
        uint32_t* c = counts + b * radix;
        std::fill(c, c + digits, 0u);
        const size_t end = std::min(n, (b + 1) * block_size);
        for (size_t i = b * block_size; i < end; ++i) ++c[(src_keys[i] >> shift) & mask];
      }
    });

    // Exclusive scan, digit-major then block-minor: block b's keys with digit d go after every smaller digit
    // and after the same digit in earlier blocks, which is what makes the pass stable.
    uint32_t sum = 0;
    bool one_digit = false;
    for (size_t d = 0; d < digits; ++d) {
      const uint32_t start = sum;
      for (size_t b = 0; b < block_count; ++b) {
        const uint32_t c = counts[b * radix + d];
        counts[b * radix + d] = sum;
        sum += c;
      }
      if (sum - start == n) one_digit = true;
    }
    if (one_digit) continue;

    tbb::parallel_for(tbb::blocked_range<size_t>(0, block_count, 1), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t b = r.begin(); b < r.end(); ++b) {
        uint32_t* offset = counts + b * radix;
        const size_t end = std::min(n, (b + 1) * block_size);
        for (size_t i = b * block_size; i < end; ++i) {
          const uint64_t k = src_keys[i];
          const uint32_t pos = offset[(k >> shift) & mask]++;
          dst_keys[pos] = k;
          dst_values[pos] = src_values[i];
        }
      }
    });
    std::swap(src_keys, dst_keys);
    std::swap(src_values, dst_values);
    result_in_scratch = !result_in_scratch;
  }

  if (result_in_scratch) {
    // The scratch buffers may be longer than n; shrinking a vector of integers frees and touches nothing.
    keys.swap(scratch.keys);
    values.swap(scratch.values);
    keys.resize(n);
    values.resize(n);
  }
}

}  // namespace raycoh
