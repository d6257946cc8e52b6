// The `simt` tracer's cache model (simt/cache_model.h) against brute-force references: a sectored LRU cache kept
// as one recency-ordered list per set, a two-level hierarchy built from it, and the documented warp schedule
// re-implemented step by step. Random address traces with locality (hot sets, sequential runs, sector
// neighbours) exercise hits, sector misses, evictions and non-power-of-two set counts. The order in which warps
// reach the caches is the timing model's (tests/timing_model_test.cpp).
#include "simt/cache_model.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <list>
#include <random>
#include <vector>

#include "core/error.h"

namespace raycoh {
namespace {

// The rules of simt/cache_model.h in their most literal form: per set, a list of (line, valid sectors), most
// recently used first.
class ReferenceCache {
 public:
  ReferenceCache(uint64_t capacity, uint32_t ways, uint32_t line_bytes, uint32_t sector_bytes)
      : ways_(ways), sectors_per_line_(line_bytes / sector_bytes), sets_(capacity / (uint64_t{line_bytes} * ways)) {
    lists_.resize(sets_);
  }
  bool access(uint64_t sector) {
    const uint64_t line = sector / sectors_per_line_;
    const uint32_t bit = 1u << (sector % sectors_per_line_);
    auto& list = lists_[line % sets_];
    for (auto it = list.begin(); it != list.end(); ++it) {
      if (it->first != line) continue;
      auto entry = *it;
      list.erase(it);
      const bool hit = (entry.second & bit) != 0;
      entry.second |= bit;
      list.push_front(entry);
      return hit;
    }
    if (list.size() == ways_) list.pop_back();
    list.push_front({line, bit});
    return false;
  }

 private:
  uint32_t ways_;
  uint64_t sectors_per_line_;
  uint64_t sets_;
  std::vector<std::list<std::pair<uint64_t, uint32_t>>> lists_;
};

// Sector addresses with the locality a traversal has: a hot working set, sequential runs and far misses.
std::vector<uint64_t> random_trace(uint64_t footprint_sectors, size_t n, uint32_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<uint64_t> out;
  out.reserve(n);
  std::uniform_int_distribution<uint64_t> any(0, footprint_sectors - 1);
  std::uniform_int_distribution<uint64_t> hot(0, footprint_sectors / 8 + 1);
  std::uniform_int_distribution<int> kind(0, 9), run(1, 12);
  while (out.size() < n) {
    const int k = kind(rng);
    if (k < 5) {
      out.push_back(hot(rng));
    } else if (k < 7) {
      const uint64_t start = any(rng);
      for (int i = run(rng); i > 0 && out.size() < n; --i) out.push_back(start + static_cast<uint64_t>(i));
    } else if (k < 9) {
      out.push_back(any(rng));
    } else {
      out.push_back(any(rng) * 1000003ull);  // far away: cold misses and set conflicts
    }
  }
  return out;
}

struct Geometry {
  uint64_t capacity;
  uint32_t ways, line, sector;
};

class CacheAgainstReference : public ::testing::TestWithParam<Geometry> {};

TEST_P(CacheAgainstReference, EveryAccessAgrees) {
  const Geometry g = GetParam();
  SectoredLruCache cache(g.capacity, g.ways, g.line, g.sector);
  ReferenceCache ref(g.capacity, g.ways, g.line, g.sector);
  EXPECT_EQ(cache.sets(), g.capacity / (uint64_t{g.line} * g.ways));
  const uint64_t capacity_sectors = g.capacity / g.sector;
  for (uint32_t seed = 1; seed <= 3; ++seed) {
    const auto trace = random_trace(capacity_sectors * (seed + 1), 100000, seed);
    size_t hits = 0;
    for (size_t i = 0; i < trace.size(); ++i) {
      const bool expect = ref.access(trace[i]);
      ASSERT_EQ(cache.access(trace[i]), expect) << "access " << i << " sector " << trace[i] << " seed " << seed;
      hits += expect;
    }
    // The traces must exercise both outcomes to mean anything.
    EXPECT_GT(hits, trace.size() / 50);
    EXPECT_LT(hits, trace.size() - trace.size() / 50);
  }
}

INSTANTIATE_TEST_SUITE_P(Geometries, CacheAgainstReference,
                         ::testing::Values(Geometry{4096, 1, 128, 32},       // direct mapped
                                           Geometry{4096, 2, 128, 32},       // two ways
                                           Geometry{8192, 4, 64, 32},        // 64-byte lines
                                           Geometry{6144, 16, 128, 32},      // 3 sets: not a power of two
                                           Geometry{2048, 16, 128, 32},      // one set: fully associative
                                           Geometry{65536, 128, 128, 32},    // the presets' 4-set L1 shape
                                           Geometry{16384, 8, 128, 128},     // unsectored
                                           Geometry{32768, 16, 1024, 32}));  // 32 sectors per line

TEST(CacheModel, SectorsAndEvictionByHand) {
  // Two sets, direct mapped, 4 sectors per line.
  SectoredLruCache c(2 * 128, 1, 128, 32);
  EXPECT_FALSE(c.access(0));  // line 0, sector 0: cold
  EXPECT_TRUE(c.access(0));
  EXPECT_FALSE(c.access(1));  // same line, other sector: a sector miss
  EXPECT_TRUE(c.access(1));
  EXPECT_FALSE(c.access(8));  // line 2 maps to set 0 too: evicts line 0
  EXPECT_FALSE(c.access(0));  // gone, with all its sectors
  EXPECT_FALSE(c.access(1));
  EXPECT_FALSE(c.access(4));  // line 1, set 1: untouched by the above
  EXPECT_TRUE(c.access(4));

  SectoredLruCache lru(3 * 64, 3, 64, 64);  // one set of 3 ways
  for (uint64_t s : {0, 1, 2}) EXPECT_FALSE(lru.access(s));
  EXPECT_TRUE(lru.access(0));   // order now 0, 2, 1 (MRU first)
  EXPECT_FALSE(lru.access(3));  // evicts 1, the least recently used
  EXPECT_TRUE(lru.access(2));
  EXPECT_TRUE(lru.access(0));
  EXPECT_FALSE(lru.access(1));
}

CacheModelConfig small_config(uint32_t sms) {
  CacheModelConfig c;
  c.sms = sms;
  c.line_bytes = 128;
  c.sector_bytes = 32;
  c.l1 = {4 * 128 * 2, 2};   // 4 sets x 2 ways
  c.l2 = {16 * 128 * 4, 4};  // 16 sets x 4 ways
  return c;
}

TEST(CacheModel, HierarchyMatchesTwoReferenceLevels) {
  const CacheModelConfig c = small_config(3);
  MemoryHierarchy h(c);
  std::vector<ReferenceCache> l1(3, ReferenceCache(c.l1.bytes, c.l1.ways, c.line_bytes, c.sector_bytes));
  ReferenceCache l2(c.l2.bytes, c.l2.ways, c.line_bytes, c.sector_bytes);
  MemoryCounters expect;
  std::mt19937 rng(7);
  const auto trace = random_trace(400, 50000, 11);
  for (uint64_t s : trace) {
    const uint32_t sm = rng() % 3;
    h.access(sm, s);
    if (l1[sm].access(s)) {
      ++expect.l1_hits;
    } else {
      ++expect.l1_misses;
      (l2.access(s) ? expect.l2_hits : expect.l2_misses) += 1;
    }
  }
  EXPECT_EQ(h.counters().l1_hits, expect.l1_hits);
  EXPECT_EQ(h.counters().l1_misses, expect.l1_misses);
  EXPECT_EQ(h.counters().l2_hits, expect.l2_hits);
  EXPECT_EQ(h.counters().l2_misses, expect.l2_misses);
  EXPECT_GT(expect.l2_hits, 0u);
  EXPECT_GT(expect.l2_misses, 0u);
}

TEST(CacheModel, GeometryErrors) {
  const CacheModelConfig c = small_config(2);
  EXPECT_NO_THROW(validate(c));
  CacheModelConfig bad = c;
  bad.l2.bytes = 3000;
  EXPECT_THROW(validate(bad), Error);
  bad = c;
  bad.sector_bytes = 48;
  EXPECT_THROW(validate(bad), Error);
  bad = c;
  bad.sms = 0;
  EXPECT_THROW(validate(bad), Error);
}

}  // namespace
}  // namespace raycoh
