// The paper's grouping in the block formulation of cuda/device_grouping.cu: one block per tile, one thread per
// pixel number i (pixel phases) or per group q (group phases), barriers between phases. Every step is a function
// of generators/grouping.h, so the block computes what the CPU tile loop computes; tests/grouping_test.cpp runs
// these phases on the host, thread by thread, and compares the batch with the CPU generator's.
//
// No phase walks the tile: a group has at most k members (the pixels whose shuffled number falls in its k
// slots), so phase 1 files each pixel under its slot (at_slot), and a group's thread or a member's thread walks
// only the group's k slots. Phase 2 ranks each hit member among its group's hit members in row-major order and
// files it there (members), so the later group phases visit the members in the CPU tile loop's order: the float
// sums of phase 6 are the CPU's, term by term.
//
// Every read of a point is load_point (core/shading_point.h): on the device, 16-byte loads of the words a phase
// uses.
#pragma once

#include "core/batch_view.h"
#include "core/shading_point.h"
#include "core/tile_grid.h"
#include "generators/grouping.h"

namespace raycoh {

enum PixelFlag : uint32_t { kPixelHit = 1u, kPixelMeanVote = 2u };

// One tile's block-shared state (CUDA shared memory): [m] per pixel number, [g] per group of the full tile.
struct TileGroups {
  uint32_t* group_of;  // [m] group in tile
  uint32_t* flags;     // [m] PixelFlag bits
  uint32_t* pos;       // [m] position of a hit pixel among its tile's hits, group by group
  Vec3* local;         // [m] tangent-space direction of a mean vote (kPixelMeanVote)
  uint32_t* count;     // [g] hit members
  uint32_t* diffuse;   // [g] diffuse-like members
  uint32_t* start;     // [g] first position of the group
  uint32_t* donor;     // [g] pixel (image index) of the donor
  uint32_t* type;      // [g] GroupType
  Vec3* shared_dir;    // [g] shared coordinates of the diffuse members' direction
  float* glossy_pdf;   // [g] hybrid=glossy: pdf of the reused glossy sample
  MaterialClass* cls;  // [m] material class of a hit pixel
  uint32_t* at_slot;   // [g k] pixel number whose shuffled number is the slot (slots >= m: none)
  uint32_t* members;   // [g k] group q's hit members in row-major order at q k + rank
};

// Bytes of a tile's state: m pixels of the full tile, g groups of at most k members.
RAYCOH_HD RAYCOH_INLINE size_t tile_groups_bytes(uint32_t m, uint32_t g, uint32_t k) {
  return static_cast<size_t>(m) * (3 * sizeof(uint32_t) + sizeof(Vec3) + sizeof(MaterialClass)) +
         static_cast<size_t>(g) * (5 * sizeof(uint32_t) + sizeof(Vec3) + sizeof(float)) +
         static_cast<size_t>(g) * k * 2 * sizeof(uint32_t);
}

// Lays the arrays out in `base` (tile_groups_bytes(m, g, k) bytes, 4-byte aligned); the byte-sized array last.
RAYCOH_HD RAYCOH_INLINE TileGroups carve_tile_groups(unsigned char* base, uint32_t m, uint32_t g, uint32_t k) {
  TileGroups s;
  auto u32 = [&base](uint32_t n) {
    auto* p = reinterpret_cast<uint32_t*>(base);
    base += sizeof(uint32_t) * n;
    return p;
  };
  s.group_of = u32(m);
  s.flags = u32(m);
  s.pos = u32(m);
  s.count = u32(g);
  s.diffuse = u32(g);
  s.start = u32(g);
  s.donor = u32(g);
  s.type = u32(g);
  s.at_slot = u32(g * k);
  s.members = u32(g * k);
  s.local = reinterpret_cast<Vec3*>(base);
  s.shared_dir = s.local + m;
  s.glossy_pdf = reinterpret_cast<float*>(s.shared_dir + g);
  s.cls = reinterpret_cast<MaterialClass*>(s.glossy_pdf + g);
  return s;
}

// What every phase of one tile reads.
struct TileBlock {
  GroupingConfig config;
  TileRect rect;
  uint32_t tile = 0, m = 0, groups = 0;
  int image_width = 0;
  const ShadingPoint* points = nullptr;
  const BsdfParams* materials = nullptr;
  TileGroups sh;
};

RAYCOH_HD RAYCOH_INLINE TileBlock make_tile_block(const GroupingConfig& c, const TileGrid& grid, uint32_t t,
                                                  const ShadingPoint* points, const BsdfParams* materials,
                                                  TileGroups sh) {
  TileBlock b;
  b.config = c;
  b.rect = grid.rect(static_cast<int>(t));
  b.tile = t;
  b.m = b.rect.area();
  b.groups = (b.m + c.k - 1) / c.k;
  b.image_width = grid.width;
  b.points = points;
  b.materials = materials;
  b.sh = sh;
  return b;
}

// Phase 1 (pixel i < m): group and flags. Returns whether the pixel has a hit.
RAYCOH_HD RAYCOH_INLINE bool phase_assign(const TileBlock& b, uint32_t i) {
  const ShadingPoint sp = load_point(b.points, b.rect.pixel(i, b.image_width));  // its last 16 bytes only
  const bool hit = has_hit(sp);
  const uint32_t slot = b.config.interleaved ? tile_shuffle(b.config, b.m, b.tile)(i) : i;
  b.sh.group_of[i] = slot / b.config.k;
  b.sh.at_slot[slot] = i;
  b.sh.flags[i] = hit ? kPixelHit : 0u;
  b.sh.cls[i] = sp.cls;
  return hit;
}

// Group q's slots: [first, last) of at_slot.
struct SlotRange {
  uint32_t first, last;
};
RAYCOH_HD RAYCOH_INLINE SlotRange group_slots(const TileBlock& b, uint32_t q) {
  const uint32_t first = q * b.config.k, last = first + b.config.k;
  return SlotRange{first, last < b.m ? last : b.m};
}

// Phase 2 (hit pixel i): its rank among its group's hit members in row-major order, and its place in `members`.
RAYCOH_HD RAYCOH_INLINE void phase_member_rank(const TileBlock& b, uint32_t i) {
  const uint32_t q = b.sh.group_of[i];
  const SlotRange r = group_slots(b, q);
  uint32_t rank = 0;
  for (uint32_t s = r.first; s < r.last; ++s) {
    const uint32_t j = b.sh.at_slot[s];
    rank += j < i && (b.sh.flags[j] & kPixelHit);
  }
  b.sh.members[q * b.config.k + rank] = i;
}

// Phase 2 (group q < groups): members and classification. The caller counts the group when census.count > 0.
RAYCOH_HD RAYCOH_INLINE GroupCensus phase_census(const TileBlock& b, uint32_t q) {
  GroupCensus census;
  const SlotRange r = group_slots(b, q);
  for (uint32_t s = r.first; s < r.last; ++s) {
    const uint32_t j = b.sh.at_slot[s];
    if (b.sh.flags[j] & kPixelHit) census.add(b.sh.cls[j]);
  }
  b.sh.count[q] = census.count;
  b.sh.diffuse[q] = census.diffuse;
  b.sh.type[q] = static_cast<uint32_t>(census.type());
  return census;
}

// Phase 3 (one thread; the GPU scans in parallel): first position of each group.
RAYCOH_HD RAYCOH_INLINE void phase_starts(const TileBlock& b) {
  uint32_t s = 0;
  for (uint32_t q = 0; q < b.groups; ++q) {
    b.sh.start[q] = s;
    s += b.sh.count[q];
  }
}

// Phase 4 (group q < groups with members): member positions in row-major order and the donor.
RAYCOH_HD RAYCOH_INLINE void phase_positions(const TileBlock& b, uint32_t q) {
  DonorSearch donor{donor_rank(b.config, group_id(b.config, b.tile, q), b.sh.diffuse[q])};
  const uint32_t* members = b.sh.members + q * b.config.k;
  for (uint32_t r = 0; r < b.sh.count[q]; ++r) {
    const uint32_t j = members[r];
    b.sh.pos[j] = b.sh.start[q] + r;
    donor.offer(b.sh.cls[j], b.rect.pixel(j, b.image_width));
  }
  b.sh.donor[q] = donor.pixel;
}

// Batch slot of hit pixel i; rank is its rank among the tile's hits in row-major order.
RAYCOH_HD RAYCOH_INLINE size_t pixel_slot(const TileBlock& b, uint32_t i, uint32_t rank, const uint32_t* offsets,
                                          const uint32_t* scanline_slots) {
  if (b.config.order == RayOrder::Scanline) return scanline_slots[b.rect.pixel(i, b.image_width)];
  return offsets[b.tile] + (b.config.order == RayOrder::Group ? b.sh.pos[i] : rank);
}

RAYCOH_HD RAYCOH_INLINE uint32_t write_pixel(const TileBlock& b, const BatchView& out, uint32_t i, size_t slot,
                                             const DirectionSample& s) {
  const uint32_t p = b.rect.pixel(i, b.image_width), q = b.sh.group_of[i];
  return write_group_ray(out, slot, load_point(b.points, p), p, s, b.tile, group_id(b.config, b.tile, q),
                         static_cast<GroupType>(b.sh.type[q]));
}

// The reference normal of group q (its donor's; frame=rotate). Groups without a diffuse member have donor
// pixel 0 and never read it.
RAYCOH_HD RAYCOH_INLINE Vec3 group_ref(const TileBlock& b, uint32_t q) {
  return load_point(b.points, b.sh.donor[q]).ns;
}

// Phase 5 (hit pixel i that is not diffuse-like): its own lobe, and its mean vote.
RAYCOH_HD RAYCOH_INLINE DirectionSample own_lobe_sample(const TileBlock& b, uint32_t i) {
  const uint32_t p = b.rect.pixel(i, b.image_width);
  const ShadingPoint sp = load_point(b.points, p);
  const DirectionSample s = sample_own_lobe(b.materials[sp.material], sp, b.config.seed, b.config.frame, p);
  if (mean_vote(b.config, sp, s, group_ref(b, b.sh.group_of[i]), b.sh.local[i])) b.sh.flags[i] |= kPixelMeanVote;
  return s;
}
// The same, written into slot `slot` of the batch. Returns the sample flags.
RAYCOH_HD RAYCOH_INLINE uint32_t phase_own_lobe(const TileBlock& b, const BatchView& out, uint32_t i, size_t slot) {
  return write_pixel(b, out, i, slot, own_lobe_sample(b, i));
}

// Phase 6 (group q < groups with diffuse members): their shared direction. hybrid=glossy re-draws the chosen
// glossy member's own sample (the same numbers as its phase 5) rather than keep every member's pdf.
RAYCOH_HD RAYCOH_INLINE SharedDirection phase_shared_direction(const TileBlock& b, uint32_t q) {
  const GroupType type = static_cast<GroupType>(b.sh.type[q]);
  const Vec3 ref = group_ref(b, q);
  SharedDirection d;
  const uint32_t* members = b.sh.members + q * b.config.k;
  const uint32_t count = b.sh.count[q];
  if (type == GroupType::Hybrid && b.config.hybrid == HybridRule::Glossy) {
    uint32_t n_glossy = 0;
    for (uint32_t r = 0; r < count; ++r) n_glossy += is_glossy_like(b.sh.cls[members[r]]);
    const uint32_t pick = glossy_rank(b.config, group_id(b.config, b.tile, q), n_glossy);
    uint32_t seen = 0;
    for (uint32_t r = 0; r < count; ++r) {
      const uint32_t j = members[r];
      if (!is_glossy_like(b.sh.cls[j]) || seen++ != pick) continue;
      const uint32_t p = b.rect.pixel(j, b.image_width);
      const ShadingPoint sp = load_point(b.points, p);
      d = glossy_direction(b.config, sp,
                           sample_own_lobe(b.materials[sp.material], sp, b.config.seed, b.config.frame, p), ref);
    }
  } else {
    GlossyMean mean;
    for (uint32_t r = 0; r < count; ++r)
      if (b.sh.flags[members[r]] & kPixelMeanVote) mean.add(b.sh.local[members[r]]);
    d = shared_direction(b.config, type, mean, b.sh.donor[q], ref);
  }
  b.sh.shared_dir[q] = d.local;
  b.sh.glossy_pdf[q] = d.glossy_pdf;
  return d;
}

// Phase 7 (diffuse-like hit pixel i): the group's direction carried to its frame.
RAYCOH_HD RAYCOH_INLINE DirectionSample reuse_sample(const TileBlock& b, uint32_t i) {
  const uint32_t p = b.rect.pixel(i, b.image_width), q = b.sh.group_of[i];
  const ShadingPoint sp = load_point(b.points, p);
  SharedDirection d;
  d.local = b.sh.shared_dir[q];
  d.glossy_pdf = b.sh.glossy_pdf[q];
  return member_direction(b.config, static_cast<GroupType>(b.sh.type[q]), b.materials[sp.material], sp, p,
                          group_ref(b, q), d);
}
// The same, written into slot `slot` of the batch. Returns the sample flags.
RAYCOH_HD RAYCOH_INLINE uint32_t phase_reuse(const TileBlock& b, const BatchView& out, uint32_t i, size_t slot) {
  return write_pixel(b, out, i, slot, reuse_sample(b, i));
}

}  // namespace raycoh
