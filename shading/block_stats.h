// Whether two renderers' images agree within their noise: per-block statistics over frames and a z-test between
// two sets of them (issue 43: the device path tracer against the CPU one, each with its own seed, so that the two
// are independent estimates of the same image).
//
// The image is cut into block x block pixel blocks (clipped at the right and bottom borders). For every frame f
// and channel c, x_f = the mean of the block's finite pixel samples of that frame (a non-finite sample is counted
// and left out, as shading/image.h's Accumulator does). Over n frames the block's estimate is the mean of the x_f
// and its variance the unbiased sample variance s^2 of the x_f (frames are independent: different random
// numbers), so the estimate's own variance is s^2 / n. Two estimates a and b of the same image then differ by
//   z = (mean_a - mean_b) / sqrt(s_a^2 / n_a + s_b^2 / n_b),
// approximately standard normal (Welch's statistic, large n). A block whose channel has |z| > limit disagrees.
// Where both variances are 0 (a constant block, e.g. all sky), z is 0 if the means are equal and infinite
// otherwise.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/vec.h"

namespace raycoh {

class BlockFrameStats {
 public:
  BlockFrameStats(int width, int height, int block = 8);
  // Adds one frame: radiance[p] is the frame's sample of pixel p = y * width + x (width x height entries).
  void add_frame(const std::vector<Vec3>& radiance);
  int blocks_x() const { return blocks_x_; }
  int blocks_y() const { return blocks_y_; }
  size_t blocks() const { return static_cast<size_t>(blocks_x_) * static_cast<size_t>(blocks_y_); }
  uint32_t frames() const { return frames_; }
  uint64_t non_finite() const { return non_finite_; }
  // Over the frames added: the mean of block b's channel c, and the unbiased variance of its per-frame values
  // (0 with fewer than two frames).
  double mean(size_t b, int c) const;
  double variance(size_t b, int c) const;

 private:
  int width_, height_, block_, blocks_x_, blocks_y_;
  uint32_t frames_ = 0;
  uint64_t non_finite_ = 0;
  std::vector<double> sum_, sum_sq_;  // 3 per block: sums of the per-frame block means and of their squares
};

// The z of every block and channel (3 per block, block-major) of a against b (same image and block size, at least
// two frames each), and where it is largest.
struct BlockZTest {
  std::vector<double> z;
  double max_abs_z = 0.0;
  size_t worst_block = 0;
  int worst_channel = 0;
  size_t beyond = 0;  // z's with |z| > limit
  // One line: the largest |z|, where, how many beyond the limit, of how many.
  std::string summary() const;
};
BlockZTest block_z_test(const BlockFrameStats& a, const BlockFrameStats& b, double limit);

}  // namespace raycoh
