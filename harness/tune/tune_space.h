// `raycoh tune`'s search space and quality budget (harness/tune/tune.cpp runs the search; harness/tune/tune_select.h
// picks).
//
// --space "tile=8x8,16x8 k=8,16 order=tile,group hybrid=paper,donor frame=duff,rotate": space-separated axes, each
// a comma-separated list of values of the generator's own parameter (generators/tangent_reuse.cpp ours_params);
// an axis left out keeps the generator's default. The settings are the product of the axes, less the cells whose
// K exceeds the tile's pixels (as `sweep` leaves them empty). `order` changes only the order of the batch, not a
// ray (tangent_reuse.cpp), so settings that differ only in order share one image measurement.
//
// --budget "ds8=1.05,flip=1.05,bias=none": the most a setting's error may be, as a ratio to NoOpt's at the same
// seeds and frame count (tune_select.h says how the seeds' spread enters):
//   ds8   relMSE of the 8x8 box-downsampled render (structure: blocks and correlated groups survive it)
//   rel   relMSE at full resolution
//   flip  HDR-FLIP of the linear render (what a viewer sees; needs the flip program, harness/image/quality.cpp)
//   bias  none: the bias test must not reject (tune_select.h); any (or left out of --budget): not checked.
// A ratio metric may be bounded by `paper` instead of a number (ds8=paper): the bound is then the paper's default
// setting's own upper end for that metric (8x8, K = 8; always measured), so that the search asks for the fastest
// setting no worse than the paper's generator at the seeds' confidence (the paper's default meets it by definition,
// and so does every setting with the same image).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "core/params.h"

namespace raycoh {

struct TuneSetting {
  std::string generator = "ours";
  int tile_w = 8, tile_h = 8, k = 8;
  std::string order = "tile", hybrid = "paper", frame = "duff";
  // "ours:tile=8x8,k=8,order=tile,hybrid=paper,frame=duff": every axis written, so that one setting has one name.
  std::string spec() const;
  // The same without order: the generator whose image the setting shares (order only reorders the batch).
  std::string image_spec() const;
  bool operator==(const TuneSetting& o) const { return spec() == o.spec(); }
};

// The paper's generator: tile (8,8), K = 8, tile order, the paper's hybrid rule and reuse frame.
TuneSetting paper_setting(const std::string& generator);

struct TuneSpace {
  std::vector<std::pair<int, int>> tiles{{8, 8}, {16, 8}, {16, 16}, {32, 8}};
  std::vector<int> ks{8, 16, 32, 64};
  std::vector<std::string> orders{"tile", "group"};
  std::vector<std::string> hybrids{"paper", "donor"};
  std::vector<std::string> frames{"duff", "rotate"};
};
// Throws raycoh::Error naming --space, the axis and what is valid.
TuneSpace parse_tune_space(const std::string& text);
std::string describe(const TuneSpace& space);
// The product of the axes (tile-major, then K, order, hybrid, frame), less K > W H cells; throws when none is left.
std::vector<TuneSetting> expand(const TuneSpace& space, const std::string& generator);

// A bound on an error ratio; ratio <= 0 means the metric is not part of the budget.
struct TuneBudget {
  double ds8 = 1.05, rel = 0, flip = 1.05;
  bool no_bias = true;  // bias=none
  // ds8=paper, rel=paper, flip=paper: bounded by the paper's default (resolved by tune_select.h's resolve_paper).
  bool ds8_paper = false, rel_paper = false, flip_paper = false;
};
TuneBudget parse_tune_budget(const std::string& text);
std::string describe(const TuneBudget& budget);

}  // namespace raycoh
