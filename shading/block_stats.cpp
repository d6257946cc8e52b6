// Per-block frame statistics and their z-test (block_stats.h).
#include "shading/block_stats.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.h"

namespace raycoh {

BlockFrameStats::BlockFrameStats(int width, int height, int block) : width_(width), height_(height), block_(block) {
  if (width < 1 || height < 1 || block < 1)
    throw Error(fmt::format("block statistics of a {}x{} image in {}-pixel blocks: all must be positive", width, height,
                            block));
  blocks_x_ = (width + block - 1) / block;
  blocks_y_ = (height + block - 1) / block;
  sum_.assign(3 * blocks(), 0.0);
  sum_sq_.assign(3 * blocks(), 0.0);
}

void BlockFrameStats::add_frame(const std::vector<Vec3>& radiance) {
  if (radiance.size() != static_cast<size_t>(width_) * static_cast<size_t>(height_))
    throw Error(
        fmt::format("block statistics: a frame of {} pixels for a {}x{} image", radiance.size(), width_, height_));
  std::vector<double> block_sum(3 * blocks(), 0.0);
  std::vector<uint32_t> count(blocks(), 0);
  for (int y = 0; y < height_; ++y)
    for (int x = 0; x < width_; ++x) {
      const Vec3 v = radiance[static_cast<size_t>(y) * width_ + x];
      if (!(std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z))) {
        ++non_finite_;
        continue;
      }
      const size_t b = static_cast<size_t>(y / block_) * blocks_x_ + x / block_;
      for (int c = 0; c < 3; ++c) block_sum[3 * b + c] += v[c];
      ++count[b];
    }
  for (size_t b = 0; b < blocks(); ++b)
    for (int c = 0; c < 3; ++c) {
      const double m = count[b] ? block_sum[3 * b + c] / count[b] : 0.0;
      sum_[3 * b + c] += m;
      sum_sq_[3 * b + c] += m * m;
    }
  ++frames_;
}

double BlockFrameStats::mean(size_t b, int c) const { return frames_ ? sum_[3 * b + c] / frames_ : 0.0; }

double BlockFrameStats::variance(size_t b, int c) const {
  if (frames_ < 2) return 0.0;
  const double n = frames_, m = sum_[3 * b + c] / n;
  // Sum of squared deviations, never negative through rounding.
  const double ss = std::max(0.0, sum_sq_[3 * b + c] - n * m * m);
  return ss / (n - 1.0);
}

BlockZTest block_z_test(const BlockFrameStats& a, const BlockFrameStats& b, double limit) {
  if (a.blocks_x() != b.blocks_x() || a.blocks_y() != b.blocks_y())
    throw Error("block z-test: the two images have different blocks");
  if (a.frames() < 2 || b.frames() < 2)
    throw Error(fmt::format("block z-test: {} and {} frames; each side needs at least two", a.frames(), b.frames()));
  BlockZTest t;
  t.z.resize(3 * a.blocks());
  for (size_t k = 0; k < a.blocks(); ++k)
    for (int c = 0; c < 3; ++c) {
      const double d = a.mean(k, c) - b.mean(k, c);
      const double se2 = a.variance(k, c) / a.frames() + b.variance(k, c) / b.frames();
      double z = 0.0;
      if (se2 > 0.0)
        z = d / std::sqrt(se2);
      else if (d != 0.0)
        z = d > 0.0 ? std::numeric_limits<double>::infinity() : -std::numeric_limits<double>::infinity();
      t.z[3 * k + c] = z;
      if (std::fabs(z) > limit) ++t.beyond;
      if (std::fabs(z) > t.max_abs_z) {
        t.max_abs_z = std::fabs(z);
        t.worst_block = k;
        t.worst_channel = c;
      }
    }
  return t;
}

std::string BlockZTest::summary() const {
  return fmt::format("max |z| {:.2f} at block {} channel {}; {} of {} beyond the limit", max_abs_z, worst_block,
                     "rgb"[worst_channel], beyond, z.size());
}

}  // namespace raycoh
