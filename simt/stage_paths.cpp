// The group kernel's trip-counted instructions; see simt/stage_paths.h. The counts are
// results/model/stage-trip-counts/group-paths-*.txt (scripts/count-stage-paths, nvcc 13, sm_90 and sm_86).
#include "simt/stage_paths.h"

#include <algorithm>
#include <cmath>

namespace raycoh {

double unrolled_loop_instructions(const UnrolledLoop& loop, double trips) {
  double left = std::max(0.0, trips), n = 0;
  if (loop.body16 > 0) {
    const double t = std::floor(left / 16);
    n += t * loop.body16;
    left -= 16 * t;
  }
  if (loop.body4 > 0) {
    const double t = std::floor(left / 4);
    n += t * loop.body4;
    left -= 4 * t;
  }
  if (loop.body1 > 0) return n + left * loop.body1;
  if (loop.body4 > 0) return n + left * loop.body4 / 4;
  return n + left * loop.body16 / 16;
}

double mlhcc_walk_instructions(double static_count, const double body[2], const KeyWalks& walks) {
  if (walks.origin <= 0 && walks.end <= 0) return static_count;
  return static_count + std::max(0.0, walks.origin - 1) * body[0] + std::max(0.0, walks.end - 1) * body[1];
}

double region_instructions(const PathRegion& r, double trips) {
  return r.straight + unrolled_loop_instructions(r.loop[0], trips) + unrolled_loop_instructions(r.loop[1], trips);
}

// Per tile: W warps (thread i = pixel i), G = ceil(m / k) groups, held by the first ceil(G / 32) warps (thread q =
// group q). A region's warps run it once (a warp runs a branch when any lane takes it); the per-slot loops run k
// times, the per-member loops k x the hit fraction times (a warp runs its longest lane's loop). A group that leaves
// the all-diffuse path is counted in a warp of its own (an upper bound of the warps it reaches).
double group_path_instructions(const GroupPathCounts& c, const GroupPath& p, double tile_pixels, double tiles) {
  const double m = std::max(1.0, tile_pixels), k = std::min(double(std::max(1, p.k)), m);
  const double warps = std::ceil(m / 32), groups = std::ceil(m / k), group_warps = std::ceil(groups / 32);
  const double members = k * std::clamp(p.hit_fraction, 0.0, 1.0);
  const double all_warps = std::max(1.0, tiles * warps), all_group_warps = std::max(1.0, tiles * group_warps);
  const double nondiffuse = std::min(1.0, p.nondiffuse_groups / all_warps);
  double n = warps * (region_instructions(c.common, warps) + region_instructions(c.member_rank, k));
  n += group_warps * (region_instructions(c.census, k) + region_instructions(c.positions, members) +
                      region_instructions(c.shared_mean, members));
  if (p.hybrid_glossy)
    n += group_warps * std::min(1.0, p.hybrid_groups / all_group_warps) * region_instructions(c.shared_glossy, members);
  n += warps * (nondiffuse * c.own_lobe.straight + c.reuse.straight +
                (p.rotate ? c.reuse_rotate.straight : c.reuse_local.straight));
  if (p.hybrid_own) n += warps * std::min(1.0, p.hybrid_groups / all_warps) * c.reuse_own.straight;
  return n / warps;
}

// Per tile of m pixels (a block of at most 256 threads; its loop over tile pieces runs once for tiles of at most 256
// pixels, as every 8x8 pass): W warps run the common code and the diffuse case (every warp is taken to hold a
// diffuse lane), the glossy and transmissive cases in the warps holding such a lane, the shared tail in either.
double noopt_path_instructions(const NooptPathCounts& c, const NooptPath& p, double tile_pixels, double tiles) {
  const double warps = std::ceil(std::min(std::max(1.0, tile_pixels), 256.0) / 32);
  const double all = std::max(1.0, tiles * warps);
  const double glossy = std::min(1.0, p.glossy_groups / all), transmissive = std::min(1.0, p.transmissive_groups / all);
  return region_instructions(c.common, warps) + c.diffuse.straight + glossy * c.glossy.straight +
         transmissive * c.transmissive.straight + std::min(1.0, glossy + transmissive) * c.tail.straight;
}

namespace {

NooptPathCounts noopt_counts(double common, const double scan[3], double diffuse, double glossy, double transmissive,
                             double tail) {
  NooptPathCounts c;
  c.common.straight = common;
  c.common.loop[0] = {scan[0], scan[1], scan[2]};
  c.diffuse.straight = diffuse;
  c.glossy.straight = glossy;
  c.transmissive.straight = transmissive;
  c.tail.straight = tail;
  return c;
}

}  // namespace

// noopt-paths-*.txt: the block scan's loop (its 16x and 4x forms); the four atomic retry loops (8 instructions
// each, sm_86 7) are counted once each in common's straight count.
NooptPathCounts noopt_paths_sm90() {
  const double scan[3] = {72, 21, 0};
  return noopt_counts(477 + 32, scan, 159, 566, 199, 73);  // 1599
}
NooptPathCounts noopt_paths_sm90_fields60() {
  const double scan[3] = {72, 21, 0};
  return noopt_counts(492 + 32, scan, 159, 567, 204, 73);  // 1620
}
NooptPathCounts noopt_paths_sm86() {
  const double scan[3] = {71, 20, 0};
  return noopt_counts(460 + 28, scan, 159, 566, 200, 73);  // 1577
}
NooptPathCounts noopt_paths_sm86_fields60() {
  const double scan[3] = {71, 20, 0};
  return noopt_counts(477 + 28, scan, 158, 571, 206, 73);  // 1604
}

namespace {

PathRegion region(double straight, UnrolledLoop a = {}, UnrolledLoop b = {}) {
  PathRegion r;
  r.straight = straight;
  r.loop[0] = a;
  r.loop[1] = b;
  return r;
}

// The phase-1 shuffle's two small loops (5 and 4 instructions) are counted once, in `common`'s straight count.
struct Listed {
  double common, scan_a[3], scan_b[3], rank_straight, rank[3], census_straight, census[2], positions_straight,
      positions, mean_straight, mean[3], glossy_straight, glossy[3], glossy_pick, own, reuse, reuse_own, rotate, local;
};

GroupPathCounts counts(const Listed& l) {
  GroupPathCounts c;
  c.common = region(l.common, {l.scan_a[0], l.scan_a[1], l.scan_a[2]}, {l.scan_b[0], l.scan_b[1], l.scan_b[2]});
  c.member_rank = region(l.rank_straight, {l.rank[0], l.rank[1], l.rank[2]});
  c.census = region(l.census_straight, {0, l.census[0], l.census[1]});
  c.positions = region(l.positions_straight, {0, 0, l.positions});
  c.shared_mean = region(l.mean_straight, {l.mean[0], l.mean[1], l.mean[2]});
  c.shared_glossy = region(l.glossy_straight, {l.glossy[0], l.glossy[1], l.glossy[2]}, {0, 0, l.glossy_pick});
  c.own_lobe = region(l.own);
  c.reuse = region(l.reuse);
  c.reuse_own = region(l.reuse_own);
  c.reuse_rotate = region(l.rotate);
  c.reuse_local = region(l.local);
  return c;
}

}  // namespace

// group-paths-sm_90.txt (the kernels since 63b5750): 7186 instructions in all.
GroupPathCounts group_paths_sm90() {
  return counts({870 + 9,
                 {84, 24, 10},
                 {76, 22, 9},
                 130,
                 {149, 41, 16},
                 40,
                 {97, 29},
                 69,
                 58,
                 566,
                 {297, 78, 20},
                 71,
                 {118, 34, 14},
                 1271,
                 1387,
                 95,
                 1132,
                 254,
                 116});
}
// group-paths-before-sm_90.txt (a26f7f6): 7241.
GroupPathCounts group_paths_sm90_fields60() {
  return counts({878 + 9,
                 {84, 24, 10},
                 {76, 22, 9},
                 130,
                 {149, 41, 16},
                 40,
                 {97, 29},
                 69,
                 58,
                 568,
                 {297, 78, 20},
                 71,
                 {118, 34, 14},
                 1276,
                 1406,
                 94,
                 1149,
                 257,
                 118});
}
// group-paths-sm_86.txt: 7015.
GroupPathCounts group_paths_sm86() {
  return counts({797 + 9,
                 {83, 23, 9},
                 {75, 21, 8},
                 121,
                 {133, 37, 14},
                 38,
                 {93, 27},
                 64,
                 57,
                 552,
                 {282, 74, 18},
                 71,
                 {117, 33, 13},
                 1269,
                 1384,
                 93,
                 1130,
                 254,
                 116});
}
// group-paths-before-sm_86.txt: 7068.
GroupPathCounts group_paths_sm86_fields60() {
  return counts({806 + 9,
                 {83, 23, 9},
                 {75, 21, 8},
                 121,
                 {133, 37, 14},
                 38,
                 {93, 27},
                 64,
                 57,
                 553,
                 {282, 74, 18},
                 71,
                 {117, 33, 13},
                 1274,
                 1403,
                 91,
                 1146,
                 257,
                 118});
}

}  // namespace raycoh
