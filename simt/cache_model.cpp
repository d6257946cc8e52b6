// The `simt` tracer's cache model: see simt/cache_model.h for the rules.
#include "simt/cache_model.h"

#include <fmt/format.h>

#include <bit>

#include "core/error.h"

namespace raycoh {
namespace {

constexpr uint32_t kL1Sets = 4;  // Accel-Sim's L1 geometry (simt/gpu_presets.cpp)

bool is_pow2(uint64_t x) { return x != 0 && (x & (x - 1)) == 0; }

const CacheModelConfig& validated(const CacheModelConfig& c) {
  validate(c);
  return c;
}

}  // namespace

uint32_t l1_ways_for(uint64_t bytes, uint32_t line_bytes) {
  const uint64_t lines = bytes / line_bytes;
  return lines >= kL1Sets ? static_cast<uint32_t>(lines / kL1Sets) : 1u;
}

void validate(const CacheModelConfig& c) {
  if (!is_pow2(c.sector_bytes) || !is_pow2(c.line_bytes) || c.line_bytes < c.sector_bytes ||
      c.line_bytes / c.sector_bytes > 32)
    throw Error(fmt::format("cache model: line {} B / sector {} B must be powers of two with 1 to 32 sectors per line",
                            c.line_bytes, c.sector_bytes));
  if (c.sms < 1 || c.sms > 1024) throw Error(fmt::format("cache model: sms={} is not in [1, 1024]", c.sms));
  for (const auto& [name, level] : {std::pair{"L1", c.l1}, std::pair{"L2", c.l2}}) {
    const uint64_t set_bytes = uint64_t{c.line_bytes} * level.ways;
    if (level.ways < 1 || level.bytes < set_bytes || level.bytes % set_bytes != 0)
      throw Error(fmt::format("cache model: {} of {} B with {} ways of {} B lines is not a whole number of sets", name,
                              level.bytes, level.ways, c.line_bytes));
  }
}

// ---- SectoredLruCache ----

SectoredLruCache::SectoredLruCache(uint64_t capacity_bytes, uint32_t ways, uint32_t line_bytes, uint32_t sector_bytes) {
  RAYCOH_CHECK(is_pow2(line_bytes) && is_pow2(sector_bytes) && line_bytes >= sector_bytes &&
                   line_bytes / sector_bytes <= 32 && ways >= 1 &&
                   capacity_bytes % (uint64_t{line_bytes} * ways) == 0 && capacity_bytes >= uint64_t{line_bytes} * ways,
               fmt::format("capacity {} ways {} line {} sector {}", capacity_bytes, ways, line_bytes, sector_bytes));
  ways_ = ways;
  sets_ = static_cast<uint32_t>(capacity_bytes / (uint64_t{line_bytes} * ways));
  sector_shift_ = static_cast<uint32_t>(std::countr_zero(line_bytes / sector_bytes));
  lines_.assign(size_t{sets_} * ways_, Line{0, 0, kNone, kNone});
  set_.assign(sets_, Set{});
  // At most half full, so that linear probing stays short.
  const uint64_t table = std::bit_ceil(uint64_t{2} * lines_.size());
  hash_.assign(table, HashEntry{});
  hash_mask_ = table - 1;
  hash_shift_ = 64 - static_cast<uint32_t>(std::countr_zero(table));
}

// Fibonacci hashing: the top bits of the product mix every bit of the line number.
uint64_t SectoredLruCache::home(uint64_t line) const {
  return hash_shift_ == 64 ? 0 : (line * 0x9E3779B97F4A7C15ull) >> hash_shift_;
}

uint32_t SectoredLruCache::find(uint64_t line) const {
  for (uint64_t i = home(line);; i = (i + 1) & hash_mask_) {
    if (hash_[i].key == line + 1) return hash_[i].slot;
    if (hash_[i].key == 0) return kNone;
  }
}

void SectoredLruCache::hash_insert(uint64_t line, uint32_t slot) {
  uint64_t i = home(line);
  while (hash_[i].key != 0) i = (i + 1) & hash_mask_;
  hash_[i] = {line + 1, slot};
}

// Backward-shift deletion (Knuth, TAOCP vol. 3, algorithm 6.4R): keeps every probe chain unbroken without
// tombstones, so lookups never slow down over a long replay.
void SectoredLruCache::hash_erase(uint64_t line) {
  uint64_t i = home(line);
  while (hash_[i].key != line + 1) i = (i + 1) & hash_mask_;
  for (uint64_t j = (i + 1) & hash_mask_;; j = (j + 1) & hash_mask_) {
    if (hash_[j].key == 0) break;
    const uint64_t h = home(hash_[j].key - 1);
    // Entry j may move into the hole at i unless its home h lies cyclically in (i, j].
    const bool home_in_between = i <= j ? (i < h && h <= j) : (i < h || h <= j);
    if (home_in_between) continue;
    hash_[i] = hash_[j];
    i = j;
  }
  hash_[i] = HashEntry{};
}

void SectoredLruCache::unlink(uint32_t set, uint32_t slot) {
  Line& l = lines_[slot];
  (l.prev == kNone ? set_[set].head : lines_[l.prev].next) = l.next;
  (l.next == kNone ? set_[set].tail : lines_[l.next].prev) = l.prev;
  l.prev = l.next = kNone;
}

void SectoredLruCache::push_front(uint32_t set, uint32_t slot) {
  Set& s = set_[set];
  lines_[slot].prev = kNone;
  lines_[slot].next = s.head;
  if (s.head != kNone) lines_[s.head].prev = slot;
  s.head = slot;
  if (s.tail == kNone) s.tail = slot;
}

bool SectoredLruCache::access(uint64_t sector) {
  const uint64_t line = sector >> sector_shift_;
  const uint32_t bit = 1u << (sector & ((uint64_t{1} << sector_shift_) - 1));
  const auto set = static_cast<uint32_t>(line % sets_);
  uint32_t slot = find(line);
  if (slot != kNone) {
    if (set_[set].head != slot) {
      unlink(set, slot);
      push_front(set, slot);
    }
    Line& l = lines_[slot];
    if (l.valid & bit) return true;
    l.valid |= bit;
    return false;
  }
  if (set_[set].used < ways_) {
    slot = set * ways_ + set_[set].used++;
  } else {
    slot = set_[set].tail;
    hash_erase(lines_[slot].tag);
    unlink(set, slot);
  }
  push_front(set, slot);
  lines_[slot].tag = line;
  lines_[slot].valid = bit;
  hash_insert(line, slot);
  return false;
}

// ---- MemoryHierarchy ----

MemoryHierarchy::MemoryHierarchy(const CacheModelConfig& c)
    : l2_(validated(c).l2.bytes, c.l2.ways, c.line_bytes, c.sector_bytes) {
  l1_.reserve(c.sms);
  for (uint32_t s = 0; s < c.sms; ++s) l1_.emplace_back(c.l1.bytes, c.l1.ways, c.line_bytes, c.sector_bytes);
}

MemoryLevel MemoryHierarchy::access(uint32_t sm, uint64_t sector, bool count) {
  const uint64_t n = count ? 1 : 0;
  if (l1_[sm].access(sector)) {
    counters_.l1_hits += n;
    return MemoryLevel::L1;
  }
  counters_.l1_misses += n;
  if (l2_.access(sector)) {
    counters_.l2_hits += n;
    return MemoryLevel::L2;
  }
  counters_.l2_misses += n;
  return MemoryLevel::Dram;
}

}  // namespace raycoh
