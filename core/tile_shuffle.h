// The per-tile pixel-number shuffle of the paper's interleaved grouping (section 3.3), shared by the CPU
// generators and the CUDA ones so both shuffle identically.
//
// s = (a i + c) mod M on M = the smallest power of two >= m, re-applied while s >= m ("cycle walking"). With
// a = 1 (mod 4) and c odd, the affine map is a full-period (single-cycle) LCG on [0, M) by the Hull-Dobell
// theorem, and walking it restricts that single cycle to [0, m), so the shuffle stays a full-period bijection for
// any m, power of two or not. a and c come from rng(seed, frame, tile, kDimTileShuffleA/C); a = 1 is excluded for
// M >= 8 because it would only rotate the numbering and leave groups contiguous.
#pragma once

#include "core/rng.h"

namespace raycoh {

struct TileShuffle {
  uint32_t a = 1, c = 0, mask = 0, m = 1;
  RAYCOH_HD uint32_t operator()(uint32_t i) const {
    uint32_t s = (a * i + c) & mask;
    while (s >= m) s = (a * s + c) & mask;
    return s;
  }
};

RAYCOH_HD RAYCOH_INLINE TileShuffle make_tile_shuffle(uint32_t m, uint32_t seed, uint32_t frame, uint32_t tile) {
  TileShuffle s;
  s.m = m;
  uint32_t size = 1;
  while (size < m) size <<= 1;
  s.mask = size - 1;
  s.a = ((rng_u32(seed, frame, tile, kDimTileShuffleA) & s.mask) & ~3u) | 1u;
  if (size >= 8 && s.a == 1u) s.a = 5u;
  s.c = (rng_u32(seed, frame, tile, kDimTileShuffleC) & s.mask) | 1u;
  s.c &= s.mask;  // M = 1: c = 0
  return s;
}

}  // namespace raycoh
