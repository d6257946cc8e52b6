// Host API of the per-frame ray pipeline on the GPU (cuda/device_primary.cu, device_generators.cu, device_per_pixel.cu,
// device_grouping.cu): primary rays and the `noopt`, `ours`, `contiguous`, `sadeghi` and `microjitter` generators,
// meant for measuring generation overheads as GPU overheads. Plain C++ (included by g++-compiled code and tests).
//
// Used by the device pipeline (cuda/device_pipeline.h: a `cuda` run with pipeline=device), which keeps the batch
// on the device; the gpu tests (tests/gpu_generators_test.cpp) check that the GPU batches equal the CPU's.
//
// Every kernel computes with the shared host/device headers (core/sampling.h, core/bsdf.h, core/rng.h) under the
// same floating-point rules as the CPU (no FMA contraction, IEEE division and square root, sincos_turns's
// polynomial instead of two libm sinf), so the batches equal the CPU generators' byte for byte: same rays in the
// same slots, same pixels, pdfs, weights, normals, classes, tiles, groups and group types, same statistics.
//
// How the GPU generators work (the CPU's result, computed in parallel):
//   primary  one thread per pixel computes its slot in the batch order directly (tile order: pixels of the tile
//            rows above, of the tiles to the left in its tile row, then row-major inside its clipped tile).
//   noopt    hit pixels per tile (one block per tile), an exclusive scan over tiles (CUB DeviceScan) for each
//            tile's first slot, then one block per tile ranks its hit pixels row-major with warp ballots and
//            writes each ray.
//   sadeghi, the same kernel with the pixels' shared numbers (generators/shared_sample.h, the rule the CPU
//   microj.  generator calls); its reused rays counted per block.
//   ours /   the same tile offsets; one block per tile (W H <= 1024: one thread per pixel) runs the phases of
//   contig.  generators/grouping_block.h: per pixel, one thread shuffles and groups its pixel number and ranks
//            itself among its group's k slots; per group, one thread counts its members and, walking only them
//            in row-major order, picks the donor and sums the glossy members' tangent-space directions in the
//            CPU's order (a float sum is only bit-identical in the same order); per pixel, one thread samples or
//            reuses and writes its ray. Every step is a function of generators/grouping.h, the one the CPU tile
//            loop calls.
// The GPU reads the CPU generator's typed Generator::device_recipe() (generators/grouping.h), never its class or
// its parameter text.
// The G-buffer is not a generator's: it is uploaded (upload) or, in the device pipeline and the device path
// tracer, made on the device by the camera pass (cuda/device_gbuffer.h) and read where it lies (use_device); it is
// not part of a generator's overhead. Not on the GPU: the `direct` ablation; ours / contiguous in scanline order
// have no fused form (launch_fused: a block makes one tile's rays).
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "core/batch_view.h"
#include "core/ray_batch.h"
#include "cuda/device_gbuffer.h"
#include "cuda/trace_kernels.h"
#include "generators/pixel_order.h"
#include "generators/primary.h"
#include "scenes/scene.h"

namespace raycoh {
class Generator;
}

namespace raycoh::cuda {

// Primary rays on the device, downloaded into `out`: equal to make_primary_rays(camera, width, height,
// make_pixel_order(width, height, order, tile_w, tile_h), seed, frame, jitter) byte for byte.
// kernel_ms (optional) receives the kernel time.
void make_primary_rays_gpu(const Camera& camera, int width, int height, RayOrder order, int tile_w, int tile_h,
                           uint32_t seed, uint32_t frame, bool jitter, PixelRays& out, float* kernel_ms = nullptr);

// sincos_turns (core/sampling.h) evaluated on the device for every u: s[i], c[i] of u[i]. For the tests that pin
// the CPU and GPU results to the same bits.
void sincos_turns_gpu(const float* u, size_t n, float* s, float* c);

// The generators with a GPU version, as refusals name them.
inline constexpr const char* kGpuGeneratorNames = "noopt, ours, contiguous, sadeghi, microjitter";

// Throws raycoh::Error unless cpu's device_recipe() has a GPU version (kGpuGeneratorNames), for ours / contiguous
// tiles of more than 1024 pixels (one thread per pixel), and with `fused` (cuda:pipeline=fused) for ours /
// contiguous in scanline order, which have no fused form.
void check_gpu_generator(const Generator& cpu, bool fused = false);

// The scene's materials on the device (uploaded once), the G-buffer (with its material table when the scene has
// textures, per frame) and batch buffers (grown on demand).
class DeviceGenerator {
 public:
  explicit DeviceGenerator(const Scene& scene);
  ~DeviceGenerator();
  DeviceGenerator(const DeviceGenerator&) = delete;
  DeviceGenerator& operator=(const DeviceGenerator&) = delete;

  // Uploads the G-buffer, generates on the device with cpu's configuration (check_gpu_generator) and downloads
  // the batch and statistics: equal to cpu.generate(scene, gbuffer, seed, out, stats).
  void generate(const GBuffer& gbuffer, uint32_t seed, const Generator& cpu, RayBatch& out, GenerationStats& stats);
  // The same in steps, for a pipeline that keeps the batch on the device: upload the G-buffer (once per frame),
  // launch the generation (queued on the default stream, between the timer's events; nothing is waited for),
  // finish (waits, checks the ray count, downloads the statistics and sets last_kernel_ms()). device_batch() is
  // the launched batch's arrays on the device (device_count() rays; tile / group / group_type null for noopt),
  // valid until the next launch; download() copies it to the host.
  void upload(const GBuffer& gbuffer);
  // In place of upload: a G-buffer already on the device (cuda/device_gbuffer.h, finished: its hit count set),
  // read where it lies (points and material table, no copy); it must stay unchanged while launches read it.
  void use_device(const DeviceGBufferView& gbuffer);
  void launch(uint32_t seed, const Generator& cpu);
  // The fused form of launch (cuda:pipeline=fused): each tile's rays are made and traced by one block with the
  // tracer's kernel form (the trace reads each ray from shared memory, where the block made it). Without
  // keep_batch: no batch, hits[pixel] for each ray's pixel (width x height entries); device_batch() is then empty.
  // With keep_batch (the device path tracer's fused first bounce, whose shading reads the batch after the trace):
  // the blocks also write the batch launch() writes, the same bytes in the same slots, and hits[i] is ray i's hit
  // (device_count() entries). Timed by the same timer (tile offsets and the kernel); finish() as after launch().
  void launch_fused(uint32_t seed, const Generator& cpu, const DeviceTracer& tracer, const TraceLaunch& trace,
                    Hit* hits, bool keep_batch = false);
  void finish(GenerationStats& stats);
  BatchView device_batch() const;
  size_t device_count() const;
  // The rays of the launched batch that is_hybrid_diffuse (core/ray_batch.h), counted on the device (one kernel,
  // then a wait: call it outside a timed span); 0 for a batch without groups or a fused launch without a batch.
  uint64_t count_hybrid_diffuse() const;
  void download(RayBatch& out) const;
  // Device time of the last generate() / finish() (every kernel and scan of it, not the transfers), CUDA events.
  float last_kernel_ms() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace raycoh::cuda
