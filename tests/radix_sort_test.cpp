// The CPU radix sort: equal to std::stable_sort by key on random batches (many duplicates, bits above key_bits
// set, 8- and 11-bit digits, every key width), permutations are bijections, and the result does not depend on
// the thread count.
#include "encoders/radix_sort.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <numeric>
#include <random>

#include "encoders/permute.h"

namespace raycoh {
namespace {

uint64_t low_bits(uint64_t k, int bits) { return bits >= 64 ? k : k & ((uint64_t{1} << bits) - 1); }

// std::stable_sort of the same (key, index) pairs by the low `bits` bits of the key.
std::vector<uint32_t> reference_order(const std::vector<uint64_t>& keys, int bits) {
  std::vector<uint32_t> order(keys.size());
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(),
                   [&](uint32_t a, uint32_t b) { return low_bits(keys[a], bits) < low_bits(keys[b], bits); });
  return order;
}

std::vector<uint64_t> random_keys(size_t n, uint64_t distinct_mask, uint32_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<uint64_t> keys(n);
  for (auto& k : keys) k = rng() & distinct_mask;
  return keys;
}

void expect_sorted_like_std(const std::vector<uint64_t>& input, int bits, int digit_bits, RadixSortScratch& scratch) {
  std::vector<uint64_t> keys = input;
  std::vector<uint32_t> values(keys.size());
  std::iota(values.begin(), values.end(), 0u);
  radix_sort_pairs(keys, values, bits, scratch, digit_bits);
  ASSERT_EQ(values, reference_order(input, bits)) << "bits " << bits << " digit " << digit_bits;
  ASSERT_TRUE(is_index_permutation(values, input.size()));
  for (size_t i = 0; i < keys.size(); ++i) ASSERT_EQ(keys[i], input[values[i]]);  // keys travel whole
}

TEST(RadixSort, EqualsStdStableSortOnRandomBatches) {
  RadixSortScratch scratch;
  uint32_t seed = 1;
  for (size_t n : {size_t{0}, size_t{1}, size_t{2}, size_t{17}, size_t{1000}, size_t{70000}, size_t{300001}}) {
    for (int bits : {1, 7, 8, 11, 16, 22, 32, 33, 63, 64}) {
      // Keys with many duplicates in the sorted bits and noise above them, which must be ignored.
      const uint64_t mask = ~uint64_t{0};
      std::vector<uint64_t> keys = random_keys(n, mask, seed++);
      for (auto& k : keys)
        if (bits < 64) k = (k & ~((uint64_t{1} << bits) - 1)) | (k % 97 & ((uint64_t{1} << bits) - 1));
      for (int digit : {8, 11}) expect_sorted_like_std(keys, bits, digit, scratch);
    }
  }
}

TEST(RadixSort, FullWidthKeysAndSkippedPasses) {
  RadixSortScratch scratch;
  // All-distinct 64-bit keys, then keys equal in their high digits (those passes are skipped), then all equal.
  expect_sorted_like_std(random_keys(200000, ~uint64_t{0}, 77), 64, 8, scratch);
  expect_sorted_like_std(random_keys(200000, 0xFFF, 78), 64, 11, scratch);
  expect_sorted_like_std(std::vector<uint64_t>(100000, 0x1234), 32, 8, scratch);
  // Already sorted and reversed input.
  std::vector<uint64_t> keys(150000);
  std::iota(keys.begin(), keys.end(), uint64_t{0});
  expect_sorted_like_std(keys, 32, 8, scratch);
  std::reverse(keys.begin(), keys.end());
  expect_sorted_like_std(keys, 32, 11, scratch);
}

TEST(RadixSort, ZeroBitsLeavesTheOrder) {
  RadixSortScratch scratch;
  std::vector<uint64_t> keys = {3, 1, 2};
  std::vector<uint32_t> values = {0, 1, 2};
  radix_sort_pairs(keys, values, 0, scratch);
  EXPECT_EQ(values, (std::vector<uint32_t>{0, 1, 2}));
}

TEST(RadixSort, ResultDoesNotDependOnTheThreadCount) {
  const std::vector<uint64_t> input = random_keys(1 << 20, 0xFFFFF, 5);
  std::vector<std::vector<uint32_t>> results;
  for (int threads : {1, 2, 5}) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    RadixSortScratch scratch;
    std::vector<uint64_t> keys = input;
    std::vector<uint32_t> values(keys.size());
    std::iota(values.begin(), values.end(), 0u);
    radix_sort_pairs(keys, values, 32, scratch);
    results.push_back(values);
  }
  EXPECT_EQ(results[0], results[1]);
  EXPECT_EQ(results[0], results[2]);
  EXPECT_EQ(results[0], reference_order(input, 32));
}

TEST(Permutation, IndexPermutationCheck) {
  EXPECT_TRUE(is_index_permutation({}, 0));
  EXPECT_TRUE(is_index_permutation({2, 0, 1}, 3));
  EXPECT_FALSE(is_index_permutation({2, 0, 0}, 3));
  EXPECT_FALSE(is_index_permutation({0, 1, 3}, 3));
  EXPECT_FALSE(is_index_permutation({0, 1}, 3));
}

}  // namespace
}  // namespace raycoh
