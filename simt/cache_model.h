// The cache model of the `simt` tracer: per-SM L1s and one shared L2, both sectored, set-associative and LRU,
// fed with the memory requests of SIMT warps in a fixed, documented order. Host only.
//
// What is modelled
//   - A cache holds lines of `line_bytes`, split into sectors of `sector_bytes` (NVIDIA since Volta: 128-byte
//     lines of four 32-byte sectors). An access names one sector. Hit: the line's tag is present and the
//     sector valid. Miss: the sector is filled; when the tag is absent, the set's least recently used line is
//     evicted and the line allocated with only that sector valid. Hits and misses both make the line the most
//     recently used. Sets are `line % sets` (real GPUs hash; node and triangle arrays are not strided, so plain
//     modulo does not create conflicts the hash would remove). Counts are in sectors, like Nsight Compute's
//     l1tex/lts sector counters.
//   - A request (one warp step's fetches) is the sorted list of distinct sectors its active lanes touch. Each
//     sector goes to the L1 of the warp's SM; an L1 miss goes to the L2; an L2 miss reads `sector_bytes` from
//     DRAM. Read-only data, so no writes, write-backs or coherence.
//   - Not modelled: the traversal stack (local memory), instruction and constant caches, L2 partitions and
//     slice hashing, MSHR merging, bandwidth and queueing. The result is a count of where sectors were found,
//     not a time.
//
// The global order (what makes the counters deterministic): thread blocks of `block_warps` consecutive warps
// are dealt to the SMs round-robin, so warp w runs on SM (w / block_warps) % sms (block_warps = 1: w % sms). Each
// SM has
// `resident_warps` slots; at the start of every scheduler cycle each SM fills its empty slots, in slot order,
// with its next warps in increasing warp order (a warp with no requests is skipped). In a cycle every occupied
// slot issues its warp's next request, slot by slot and, within a slot, SM by SM (j outer, s inner), so the
// L2 sees the SMs interleaved the way concurrently running SMs interleave. A warp leaves its slot after its
// last request. This mirrors a GPU's block scheduler refilling an SM as soon as a warp finishes, at the
// granularity of one memory request per warp per cycle. It depends only on the traces and the configuration,
// never on thread count or on how the traces were produced.
//
// Presets (CacheModelConfig below; every number can be overridden through the tracer's parameters)
//   rtx3060  GA106: 28 SMs (3584 CUDA cores / 128 per SM, NVIDIA GeForce RTX 3060 specifications); 128 KB
//            unified L1/shared memory per SM (NVIDIA Ampere GA102 whitepaper, GA10x SM), all of it L1 because
//            the traversal kernel uses no shared memory (compute capability 8.6 allows a 0 KB carveout, CUDA
//            C++ Programming Guide / Ampere Tuning Guide); 3 MB L2 (GA10x pairs 512 KB of L2 with each 32-bit
//            memory controller, GA102 whitepaper; the 3060 has a 192-bit bus, i.e. six controllers).
//   h100     H100 SXM5: 132 SMs, 256 KB unified L1/shared memory per SM (all of it L1, as above), 50 MB L2
//            (NVIDIA H100 Tensor Core GPU Architecture whitepaper; Chips and Cheese, "Nvidia's H100: Funny L2,
//            and Tons of Bandwidth", 2023). The L2 is modelled as one 50 MB cache, not as two partitions.
//   Both: 128-byte lines of 32-byte sectors (CUDA C++ Best Practices Guide, "Coalesced Access to Global
//   Memory"). Associativity is not published; we take the values that Accel-Sim (Khairy et al., ISCA 2020)
//   tuned against the hardware in its tested-cfgs SM86_RTX3070 and SM80_A100: an L1 of 4 sets (so
//   capacity / 512 B ways) and a 16-way L2. resident_warps = 32: the register-limited occupancy of a
//   64-register traversal kernel (65536 registers / (64 x 32)); the SMs allow 48 (CC 8.6) and 64 (CC 9.0).
//   block_warps = 2 by default: one 64-thread block per 8x8 tile, as the GPU kernel launches it (DESIGN.md
//   section 1), which keeps both warps of a tile on one SM and so changes what its L1 shares.
//
// Cost weights (cycles) used by the modeled cost in simt/simt.h: L1 hit, L2 hit and DRAM latencies from the same
// Accel-Sim configurations (rtx3060: gpgpu_l1_latency 39, gpgpu_l2_rop_latency 187, + dram_latency 254 = 441;
// h100 from SM80_A100, the closest tuned data-centre part: 34, 200, 200 + 190 = 390), of the order Jia et al.
// measured ("Dissecting the NVIDIA Volta GPU Architecture via Microbenchmarking", 2018, and the Turing T4 report,
// 2019: L1 hits of about 30 cycles, L2 hits of about 190). Warp-step weights are issue slots, one per warp
// instruction, counted from core/traverse.h and rounded: a node step (four 16-byte loads, two slab tests of about
// 25 operations, ordering and the stack) ~ 70, a triangle test (shear, three edge functions, plane-equation t,
// division) ~ 70, the leaf-step bookkeeping ~ 10. The weights are not tracer parameters: CoherenceCounters keeps
// every term's count, so a script can re-weigh a result without re-running it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace raycoh {

// Weights of the modeled cost (simt/simt.h), in cycles.
struct CostWeights {
  double node_step = 70.0;      // per warp node step (issue slots)
  double leaf_step = 10.0;      // per warp leaf step
  double triangle_step = 70.0;  // per warp triangle sub-step
  double l1_hit = 39.0;         // per sector found in L1
  double l2_hit = 187.0;        // per sector missed in L1, found in L2
  double dram = 441.0;          // per sector read from DRAM
};

struct CacheLevelConfig {
  uint64_t bytes = 0;
  uint32_t ways = 1;  // sets = bytes / (line_bytes * ways)
};

struct CacheModelConfig {
  std::string preset;            // "rtx3060", "h100" or "" (hand-made)
  uint32_t sms = 28;             // [1, 1024]
  uint32_t resident_warps = 32;  // slots per SM, [1, 64]
  uint32_t block_warps = 2;      // consecutive warps per thread block, all on one SM, [1, 32]
  uint32_t line_bytes = 128;     // power of two, >= sector_bytes, <= 32 sectors
  uint32_t sector_bytes = 32;    // power of two
  CacheLevelConfig l1;
  CacheLevelConfig l2;
  CostWeights cost;
};

std::vector<std::string> cache_preset_names();  // {"rtx3060", "h100"}
// Throws raycoh::Error for an unknown name, naming the valid ones.
CacheModelConfig cache_preset(const std::string& name);
// L1 ways for a capacity when the set count is kept at the presets' 4 (Accel-Sim's L1 geometry).
uint32_t l1_ways_for(uint64_t bytes, uint32_t line_bytes);
// Throws raycoh::Error naming the offending value when a geometry is not realisable (non-power-of-two sizes,
// a capacity that is not a whole number of sets, zero SMs or slots).
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

// Per-SM L1s in front of one shared L2.
class MemoryHierarchy {
 public:
  explicit MemoryHierarchy(const CacheModelConfig& config);
  void access(uint32_t sm, uint64_t sector);
  const MemoryCounters& counters() const { return counters_; }

 private:
  std::vector<SectoredLruCache> l1_;
  SectoredLruCache l2_;
  MemoryCounters counters_;
};

// One warp's memory requests in issue order: request r is sectors[begin(r), request_end[r]), with
// begin(0) = 0 and begin(r) = request_end[r - 1]. Sector numbers are byte address / sector_bytes.
struct WarpTrace {
  std::vector<uint32_t> sectors;
  std::vector<uint32_t> request_end;
  size_t requests() const { return request_end.size(); }
};

// Replays warp traces through a MemoryHierarchy in the global order above. The traces may arrive in pieces:
// run(traces, ready) replays cycles as long as every warp they need is below `ready` (traces[w] complete for
// w < ready) and returns before the first cycle that needs a later warp, so that the next warps can be traced
// meanwhile; the result does not depend on where it paused. The trace of a warp is freed when it finishes.
class WarpScheduleReplay {
 public:
  WarpScheduleReplay(const CacheModelConfig& config, size_t warp_count);
  void run(std::vector<WarpTrace>& traces, size_t ready);
  bool done() const { return done_; }
  const MemoryCounters& counters() const { return memory_.counters(); }
  uint64_t cycles() const { return cycles_; }  // scheduler cycles replayed so far

 private:
  struct Slot {
    size_t warp = SIZE_MAX;  // SIZE_MAX = empty
    uint32_t request = 0;
  };
  // Fills the empty slots of every SM; false when a slot needs a warp >= ready.
  bool refill(std::vector<WarpTrace>& traces, size_t ready);

  MemoryHierarchy memory_;
  size_t warp_of(uint32_t sm, size_t k) const;  // the k-th warp SM `sm` runs

  uint32_t sms_, resident_, block_;
  size_t warp_count_;
  std::vector<Slot> slots_;   // sm * resident + slot
  std::vector<size_t> next_;  // per SM: how many of its warps it has taken
  uint64_t cycles_ = 0;
  bool done_ = false;
};

}  // namespace raycoh
