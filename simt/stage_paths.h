// The group kernel's instructions on the path a pass runs (the trip-counted instruction term of the stage model,
// docs/simt-model.md section 3): its SASS split by region (scripts/count-stage-paths: the source function each
// instruction was inlined from, each loop's body and unroll factor), each region run only by the warps and as many
// times as the workload gives it. MODELED; a lower layer of simt/stage_model.h (plain counts and arithmetic).
#pragma once

#include <cstdint>

namespace raycoh {

// One source loop as nvcc unrolls it: the SASS body of its 16x, 4x and 1x loops (0: that form absent).
struct UnrolledLoop {
  double body16 = 0, body4 = 0, body1 = 0;
};
// Instructions of `trips` iterations: the 16x loop while 16 remain, then the 4x loop, then the 1x loop (nvcc's
// order); iterations left when the 1x form is absent cost the 4x body's share each.
double unrolled_loop_instructions(const UnrolledLoop& loop, double trips);

// A region: instructions outside loops (run once) and up to two source loops.
struct PathRegion {
  double straight = 0;
  UnrolledLoop loop[2];
};
// A region run once with its loops iterated `trips` times each.
double region_instructions(const PathRegion& r, double trips);

// The group kernel's regions (scripts/count-stage-paths prints them; results/model/stage-trip-counts/).
struct GroupPathCounts {
  PathRegion common;         // every warp; its loops: the two block scans' loops over the block's warps
  PathRegion member_rank;    // every warp with a hit; loop[0] over the group's k slots
  PathRegion census;         // warps holding group threads; loop[0] over k slots
  PathRegion positions;      // warps holding group threads; loop[0] over the group's hit members
  PathRegion shared_mean;    // warps holding group threads of groups with diffuse members; loop[0] over members
  PathRegion shared_glossy;  // the same, hybrid=glossy's hybrid groups: loop[0] and loop[1] over members
  PathRegion own_lobe;       // warps with a hit lane that is not diffuse-like
  PathRegion reuse;          // warps with a diffuse-like hit lane
  PathRegion reuse_own;      // hybrid=independent's hybrid members
  PathRegion reuse_rotate;   // frame=rotate
  PathRegion reuse_local;    // frame=duff
  bool empty() const { return common.straight == 0; }
};

// What the group kernel runs on one pass: the tile, k, the rule and frame, and how many of its groups leave the
// all-diffuse path (the pass's own group counts, workload columns of its row; no time).
struct GroupPath {
  int k = 0;                     // 0: unknown (the static count is used)
  bool rotate = false;           // frame=rotate (else duff)
  bool hybrid_glossy = false;    // hybrid=glossy
  bool hybrid_own = false;       // hybrid=independent
  double hit_fraction = 1;       // rays / pixels
  double nondiffuse_groups = 0;  // groups with a member that is not diffuse-like (glossy + hybrid + independent)
  double hybrid_groups = 0;
};

// The per-pixel noopt kernel by region (scripts/count-stage-paths --noopt): sample_direction's cases and the rest.
struct NooptPathCounts {
  PathRegion common;  // every warp; loop[0]: the block scan's loop over the block's warps
  PathRegion diffuse, glossy, transmissive;
  PathRegion tail;  // the check and return of the two non-diffuse cases
  bool empty() const { return common.straight == 0; }
};
// What the noopt kernel runs on one pass: how many warps hold a glossy-like and a transmissive lane, from the
// scene's group counts (the same G-buffer's ours pass: glossy + hybrid groups, independent groups), each group in a
// warp of its own (an upper bound), at most every warp.
struct NooptPath {
  bool known = false;  // false: the static count is used
  double glossy_groups = 0, transmissive_groups = 0;
};
double noopt_path_instructions(const NooptPathCounts& c, const NooptPath& p, double tile_pixels, double tiles);
NooptPathCounts noopt_paths_sm90();
NooptPathCounts noopt_paths_sm90_fields60();
NooptPathCounts noopt_paths_sm86();
NooptPathCounts noopt_paths_sm86_fields60();

// MLHCC's key kernel: the mean over warps of each cut walk's iterations, the warp's largest lane
// (bench/mlhcc_walks.cpp counts them on the pass), and the SASS body of each walk's loop (count-stage-instructions'
// loop bodies: the origin's walk, then the end point's). The static count holds each body once.
struct KeyWalks {
  double origin = 0, end = 0;  // 0: unknown (the static count is used)
};
double mlhcc_walk_instructions(double static_count, const double body[2], const KeyWalks& walks);

// Mean instructions per warp of the group kernel on tiles of `tile_pixels` pixels, `tiles` tiles in all.
double group_path_instructions(const GroupPathCounts& c, const GroupPath& p, double tile_pixels, double tiles);

// The sm_90 and sm_86 counts, for the kernels since 63b5750 and before it (Fields60).
GroupPathCounts group_paths_sm90();
GroupPathCounts group_paths_sm90_fields60();
GroupPathCounts group_paths_sm86();
GroupPathCounts group_paths_sm86_fields60();

}  // namespace raycoh
