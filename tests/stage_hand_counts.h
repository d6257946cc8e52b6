// The group kernel's regions with hand-countable sizes, for the stage model's tests (stage_paths_test.cpp,
// stage_latency_test.cpp): each region's straight instructions and plain (1x) loop bodies, so that a path's count
// can be written out by hand.
#pragma once

#include "simt/stage_paths.h"

namespace raycoh::test {

inline GroupPathCounts hand_counts() {
  GroupPathCounts c;
  c.common.straight = 100;
  c.common.loop[0] = {0, 0, 2};  // a loop over the block's warps
  c.member_rank.straight = 10;
  c.member_rank.loop[0] = {0, 0, 3};
  c.census.straight = 20;
  c.census.loop[0] = {0, 0, 5};
  c.positions.straight = 30;
  c.positions.loop[0] = {0, 0, 7};
  c.shared_mean.straight = 40;
  c.shared_mean.loop[0] = {0, 0, 11};
  c.shared_glossy.straight = 300;
  c.shared_glossy.loop[0] = {0, 0, 13};
  c.shared_glossy.loop[1] = {0, 0, 17};
  c.own_lobe.straight = 1000;
  c.reuse.straight = 50;
  c.reuse_own.straight = 500;
  c.reuse_rotate.straight = 70;
  c.reuse_local.straight = 60;
  return c;
}

}  // namespace raycoh::test
