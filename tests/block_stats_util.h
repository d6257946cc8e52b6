// Per-block frame statistics of a CPU path-traced render (shading/block_stats.h), shared by the block z-test's
// CPU tests and the device path tracer's gpu tests.
#pragma once

#include <cmath>
#include <limits>
#include <vector>

#include "shading/block_stats.h"
#include "shading/path_tracer.h"

namespace raycoh::test {

// One frame's sample per pixel (NaN where the sample was not finite) of a fresh accumulator holding that frame.
inline std::vector<Vec3> frame_samples(const Accumulator& acc) {
  const Image img = acc.mean();
  std::vector<Vec3> out(img.pixels());
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (size_t p = 0; p < out.size(); ++p) out[p] = acc.non_finite_samples(p) ? Vec3(nan) : img.at(p);
  return out;
}

// Frames first .. first + frames - 1 of the CPU path tracer, each scaled by `scale`, in block statistics.
inline BlockFrameStats cpu_block_stats(const Scene& scene, Tracer& tracer, Generator& generator,
                                       const RenderSettings& rs, int frames, float scale = 1.f, int block = 8) {
  PathTracer pt(scene, tracer, generator, rs);
  BlockFrameStats stats(rs.width, rs.height, block);
  for (int f = 0; f < frames; ++f) {
    Accumulator acc(rs.width, rs.height);
    pt.render_frame(static_cast<uint32_t>(f), acc);
    std::vector<Vec3> samples = frame_samples(acc);
    for (Vec3& v : samples) v = v * scale;
    stats.add_frame(samples);
  }
  return stats;
}

}  // namespace raycoh::test
