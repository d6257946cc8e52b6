// Two ray batches held equal column by column, bit for bit: every column of RAYCOH_BATCH_COLUMNS
// (core/ray_batch.h), so a column added there is compared by every device test without a change here.
#pragma once

#include <gtest/gtest.h>

#include "core/ray_batch.h"
#include "tests/test_util.h"

namespace raycoh::test {

// The same size, and no element of any column differing (an empty group column equals an empty one).
inline void expect_same_columns(const RayBatch& a, const RayBatch& b) {
  ASSERT_EQ(a.size(), b.size());
#define RAYCOH_EXPECT_SAME_COLUMN(name, T, grouped) EXPECT_EQ(differing(a.name, b.name), 0u) << #name;
  RAYCOH_BATCH_COLUMNS(RAYCOH_EXPECT_SAME_COLUMN)
#undef RAYCOH_EXPECT_SAME_COLUMN
}

}  // namespace raycoh::test
