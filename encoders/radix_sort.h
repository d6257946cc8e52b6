// Stable LSD radix sort of (key, value) pairs on the CPU, parallel with oneTBB; the sort step of every
// reordering encoder (docs/design.md section 3; CUB's radix sort takes its place on the GPU).
//
// Parameters
//   key_bits    int  -  [0, 64]: only the low key_bits bits of each key are sorted on; higher bits are carried
//                       along but ignored (an encoder's k-bit keys are right-aligned, so this is exactly the key)
//   digit_bits  int  8  [1, 16]: bits per pass (8 or 11 in practice); the last pass takes what is left
// Each pass histograms fixed blocks of the input in parallel, scans the counts digit-major and block-minor, and
// scatters every block in input order, so the result is the stable order whatever the thread count. A pass
// whose digit is the same for every key is skipped: it cannot change the order.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace raycoh {

constexpr int kDefaultRadixDigitBits = 8;

// Ping-pong buffers and per-block counts, kept between calls so that sorting allocates nothing once warm.
struct RadixSortScratch {
  std::vector<uint64_t> keys;
  std::vector<uint32_t> values;
  std::vector<uint32_t> counts;
  // Sizes the buffers for n pairs ahead of a timed sort.
  void reserve(size_t n);
};

// Sorts keys and values together by the low key_bits bits of the keys, stably (equal keys keep their input
// order). keys.size() == values.size() <= 2^32 - 1. The result is left in keys and values, which may have
// exchanged their storage with the scratch buffers.
void radix_sort_pairs(std::vector<uint64_t>& keys, std::vector<uint32_t>& values, int key_bits,
                      RadixSortScratch& scratch, int digit_bits = kDefaultRadixDigitBits);

}  // namespace raycoh
