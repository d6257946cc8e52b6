// MLHCC: multilevel hierarchy cut code (Xiang et al. 2023, "Faster Ray Tracing through Hierarchy Cut Code").
// Instead of a grid in space, a ray is encoded by where its origin and estimated end point lie in nested cuts of
// the BVH itself, so rays with equal codes descend the same subtrees (the paper's remedy for the "boundary drift"
// of space-filling-curve keys). The public record gives only the idea (cuts of the BVH, lambda = 0.125 sets how
// fine each cut level is, 32-bit codes, a compression of the per-level codes); the exact rule implemented is:
//
// 1. Cuts. A cut is a set of tree elements (inner nodes or leaves) that meets every root-to-leaf path once.
//    Level 0 is the root. Below a level-l cut node P, the level-(l+1) cut nodes are the first elements e on each
//    downward path whose box's surface area is at most lambda x P's, or the leaf ending the path when none is
//    that small (a leaf ends its path's cuts). Surface area because it is the SAH's measure of how likely a ray
//    is to visit a box, and it stays meaningful for flat boxes where volume is 0. For a cube halved evenly,
//    lambda = 0.125 means box sides shrink by about sqrt(8) per level: roughly 8 to 32 cut nodes under each.
// 2. Ranks. The cut nodes beneath one parent are numbered 0, 1, 2, ... in the BVH's depth-first order (child 0
//    first, the order of the flat node array), so a code orders rays like the tree orders space. Compression
//    (ranks=compressed, the default): level l's field is only as wide as the largest sibling set at that level
//    needs, ceil(log2(max siblings)), instead of the ceil(log2(level size)) a rank within the whole level needs
//    (ranks=global, kept to measure what the compression buys).
// 3. Point location. A point, clamped into the scene box (NaN to its low corner), descends from the root into
//    the child whose box is nearer (distance 0 inside); on a tie (inside both overlapping boxes) into the smaller
//    box, then child 0. Every cut node on the way contributes its rank. No triangles are read: one node per tree level.
// 4. Code. Level by level from level 1: the origin's rank, then the end point's rank, each in that level's
//    width, packed from the most significant bit and truncated to 64 bits; a k-bit key is the top k bits. A
//    level below the leaf where a path ended contributes 0. The end point is o + L d with L estimated exactly as
//    in twopoint (encoders/twopoint.cpp). The descent stops once the key's bits are full, so a 32-bit key costs
//    only the top few levels. `details()` reports the levels, their widths and sizes.
//
// Parameters: mlhcc_params() below (the paper's code length is 32 bits; a smaller lambda makes more, finer levels).
// Recorded with them: box=lo..hi, the scene bounds points are clamped to. Needs the scene's BVH.
#include <fmt/format.h>

#include <memory>

#include "core/error.h"
#include "encoders/key_encoder.h"
#include "encoders/mlhcc_cuts.h"

namespace raycoh {

const ParamTable& mlhcc_params() {
  static const ParamTable table = {
      key_bits_param(),
      float_param("lambda", 0.125f, 0.001f, 0.999f, "surface-area ratio between successive cut levels"),
      end_point_param(),
      choice_param("points", "both", {"both", "origin"}, "code origin and end point, or the origin alone"),
      choice_param("ranks", "compressed", {"compressed", "global"},
                   "per-level widths from sibling sets or from whole levels"),
  };
  return table;
}

std::unique_ptr<Encoder> make_mlhcc_encoder(ParamSet& params, const EncoderContext& context) {
  const int bits = read_key_bits(params);
  const float lambda = params.get_float("lambda");
  const float length = params.get_float("L");
  const bool with_end = params.get_choice("points") == "both";
  const MlhccRanks ranks = params.get_choice("ranks") == "compressed" ? MlhccRanks::Compressed : MlhccRanks::Global;
  const Bounds box = context.bounds;
  const std::string canonical = finish_encoder_params(params, box);
  if (!context.bvh) throw Error(fmt::format("{}: needs the scene's BVH, and none was given", params.owner()));

  // The table is shared with the code function, which keeps a view of it: the encoder owns both.
  auto table = std::make_shared<const MlhccCutTable>(build_mlhcc_cuts(*context.bvh, lambda, ranks));
  const std::string details = table->summary();
  return make_recipe_encoder(
      "mlhcc", KeyRecipe{KeyKind::Mlhcc, bits, box, length, lambda, with_end, ranks == MlhccRanks::Global}, canonical,
      table->view(), table, details);
}

}  // namespace raycoh
