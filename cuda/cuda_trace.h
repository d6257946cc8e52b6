// Host API of the CUDA closest-hit path (compiled by nvcc; callable from g++ code). The kernel runs the same
// core/traverse.h traversal as the CPU tracers, so hits must match the `cpu` tracer exactly.
// The timed, persistent-thread GPU tracer with warp counters builds on this (DESIGN.md section 4).
#pragma once

#include <cstddef>
#include <string>

#include "core/bvh.h"
#include "core/ray.h"

namespace raycoh::cuda {

// Number of usable CUDA devices; 0 when there is no GPU or no driver (any CUDA error counts as "no GPU").
int device_count();
// Name and compute capability of device 0, or "" without a GPU.
std::string device_name();

// Uploads the BVH and rays, traces every ray with one thread each, downloads the hits. kernel_ms receives the
// kernel time measured with CUDA events (transfers excluded). Throws raycoh::Error on any CUDA error.
void trace_closest(const BvhView& bvh, const Ray* rays, size_t count, Hit* hits, float* kernel_ms);

}  // namespace raycoh::cuda
