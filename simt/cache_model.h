// The cache model of the `simt` tracer: per-SM L1s and one shared L2, both sectored, set-associative and LRU.
// Host only. The timing model (simt/timed_replay.h) decides the order in which warps' requests reach it.
//
// What is modelled
//   - A cache holds lines of `line_bytes`, split into sectors of `sector_bytes` (NVIDIA since Volta: 128-byte
//     lines of four 32-byte sectors). An access names one sector. Hit: the line's tag is present and the
//     sector valid. Miss: the sector is filled; when the tag is absent, the set's least recently used line is
//     evicted and the line allocated with only that sector valid. Hits and misses both make the line the most
//     recently used. Sets are `line % sets` (real GPUs hash; node and triangle arrays are not strided, so plain
//     modulo does not create conflicts the hash would remove). Counts are in sectors, like Nsight Compute's
//     l1tex/lts sector counters.
//   - Each sector goes to the L1 of the warp's SM; an L1 miss goes to the L2; an L2 miss reads `sector_bytes`
//     from DRAM. Read-only data, so no writes, write-backs or coherence.
//   - Not modelled: the traversal stack (local memory), instruction and constant caches, L2 partitions and
//     slice hashing, MSHR merging. Presets and their sources: simt/gpu_presets.cpp.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace raycoh {

struct CacheLevelConfig {
  uint64_t bytes = 0;
  uint32_t ways = 1;  // sets = bytes / (line_bytes * ways)
};

struct CacheModelConfig {
  uint32_t sms = 28;           // [1, 1024]
  uint32_t line_bytes = 128;   // power of two, >= sector_bytes, <= 32 sectors
  uint32_t sector_bytes = 32;  // power of two
  CacheLevelConfig l1;
  CacheLevelConfig l2;
};
// L1 ways for a capacity when the set count is kept at the presets' 4 (Accel-Sim's L1 geometry).
uint32_t l1_ways_for(uint64_t bytes, uint32_t line_bytes);
// Throws raycoh::Error naming the offending value when a geometry is not realisable (non-power-of-two sizes,
// a capacity that is not a whole number of sets, zero SMs).
void validate(const CacheModelConfig& config);

// One set-associative, sectored LRU cache (the rules above). access() is O(1) for any associativity: tags are
// found through an open-addressing hash table, and each set keeps its lines in a doubly linked recency list.
class SectoredLruCache {
 public:
  SectoredLruCache(uint64_t capacity_bytes, uint32_t ways, uint32_t line_bytes, uint32_t sector_bytes);
  // `sector` = byte address / sector_bytes. Returns true on a hit; a miss fills the sector.
  bool access(uint64_t sector);
  uint32_t sets() const { return sets_; }
  uint32_t ways() const { return ways_; }

 private:
  static constexpr uint32_t kNone = 0xFFFFFFFFu;
  uint64_t home(uint64_t line) const;
  uint32_t find(uint64_t line) const;
  void hash_insert(uint64_t line, uint32_t slot);
  void hash_erase(uint64_t line);
  void unlink(uint32_t set, uint32_t slot);
  void push_front(uint32_t set, uint32_t slot);

  // Packed so that an access touches few host cache lines: the 50 MB L2 preset alone has 400k lines.
  struct Line {
    uint64_t tag;    // line number
    uint32_t valid;  // valid-sector mask
    uint32_t prev, next;
  };
  struct Set {
    uint32_t head = kNone, tail = kNone, used = 0;  // MRU slot, LRU slot, slots in use
  };
  struct HashEntry {
    uint64_t key = 0;  // line + 1; 0 = empty
    uint32_t slot = kNone;
  };

  uint32_t sets_ = 0, ways_ = 0;
  uint32_t sector_shift_ = 0;  // log2(sectors per line)
  std::vector<Line> lines_;    // slot = set * ways + way
  std::vector<Set> set_;
  std::vector<HashEntry> hash_;
  uint64_t hash_mask_ = 0;
  uint32_t hash_shift_ = 64;
};

struct MemoryCounters {
  uint64_t l1_hits = 0, l1_misses = 0;
  uint64_t l2_hits = 0, l2_misses = 0;  // l2 accesses = l1_misses
};

// Where a sector was found.
enum class MemoryLevel : uint8_t { L1, L2, Dram };

// Per-SM L1s in front of one shared L2.
class MemoryHierarchy {
 public:
  explicit MemoryHierarchy(const CacheModelConfig& config);
  // `count` = false: the access changes the caches but not the counters (the ray fetches of the timing model).
  MemoryLevel access(uint32_t sm, uint64_t sector, bool count = true);
  const MemoryCounters& counters() const { return counters_; }

 private:
  std::vector<SectoredLruCache> l1_;
  SectoredLruCache l2_;
  MemoryCounters counters_;
};

}  // namespace raycoh
