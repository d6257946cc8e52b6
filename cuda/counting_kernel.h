// The warp-synchronous counting kernel (cuda/counting_kernel.cu): one warp per 32 consecutive rays runs the classic
// while-while loop of core/traverse.h under the stepping and counting rules of simt/simt.h and writes each warp's
// step and per-ray counters. Host API for cuda/trace_kernels.cu; a header for .cu files.
#pragma once

#include <cstddef>
#include <cstdint>

#include "core/alpha_mask.h"
#include "core/bvh.h"
#include "core/ray.h"
#include "core/warp_counters.h"

namespace raycoh::cuda {

// Launches the counting kernel on the default stream (blocks x block threads, one warp per 32 rays).
void launch_counting(const BvhView& bvh, const NoAlphaTest& filter, unsigned blocks, int block, const Ray* rays,
                     const uint32_t* order, size_t count, Hit* hits, const SimtConfig& layout, WarpStepCounters* out,
                     size_t warps);
void launch_counting(const BvhView& bvh, const AlphaTest& filter, unsigned blocks, int block, const Ray* rays,
                     const uint32_t* order, size_t count, Hit* hits, const SimtConfig& layout, WarpStepCounters* out,
                     size_t warps);

}  // namespace raycoh::cuda
