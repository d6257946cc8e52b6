// The host side of every GPU generator and the tile offsets' kernels (cuda/device_generators.h explains the
// method; the primary rays are in device_primary.cu, noopt, sadeghi and microjitter in device_per_pixel.cu, the
// `ours` / `contiguous` grouping in device_grouping.cu).
// The per-ray math is the shared host/device code the CPU generators call (core/own_lobe.h, core/batch_view.h,
// core/tile_grid.h, generators/grouping.h, generators/shared_sample.h), pinned by the gpu-labelled tests
// (tests/gpu_generators_test.cpp). The device pipeline (cuda/device_pipeline.cpp) runs upload / launch / finish and
// keeps the batch on the device. (No fmt here: its consteval format strings do not compile under nvcc 13.)
#include <cuda_runtime.h>

#include <cub/device/device_scan.cuh>
#include <string>

#include "core/error.h"
#include "core/own_lobe.h"
#include "core/shading_point.h"
#include "cuda/cuda_check.cuh"
#include "cuda/device_batch.cuh"
#include "cuda/device_common.cuh"
#include "cuda/device_generators.h"
#include "cuda/pixel_numbers.cuh"
#include "generators/generator.h"

namespace raycoh::cuda {

namespace {

// ---- tile offsets -----------------------------------------------------------------------------------------------

// counts[t] = hit pixels of tile t (one block per tile). Reads one word of each point (prim: a 4-byte load, where
// load_point would move the point's last 16 bytes).
__global__ void tile_hits_kernel(const ShadingPoint* points, TileGrid grid, uint32_t* counts) {
  const int t = blockIdx.x;
  int x0, y0, w, h;
  grid.rect(t, x0, y0, w, h);
  const int m = w * h;
  int hits = 0;
  for (int base = 0; base < m; base += blockDim.x) {
    const int i = base + static_cast<int>(threadIdx.x);
    const bool hit = i < m && has_hit(points[static_cast<size_t>(y0 + i / w) * grid.width + x0 + i % w]);
    hits += __syncthreads_count(hit);
  }
  if (threadIdx.x == 0) counts[t] = static_cast<uint32_t>(hits);
}

// flags[p] = 1 for hit pixels (scanline slots).
__global__ void hit_flags_kernel(const ShadingPoint* points, size_t n, uint32_t* flags) {
  const size_t p = blockIdx.x * static_cast<size_t>(blockDim.x) + threadIdx.x;
  if (p < n) flags[p] = has_hit(points[p]) ? 1u : 0u;
}

}  // namespace

// ---- host side --------------------------------------------------------------------------------------------------

namespace {

// What the GPU runs: the CPU generator's typed recipe (noopt, sadeghi / microjitter's sharing, or the grouping of
// ours / contiguous).
DeviceRecipe gpu_recipe(const Generator& cpu, bool fused) {
  const DeviceRecipe r = cpu.device_recipe();
  if (r.kind == DeviceRecipe::Kind::None)
    throw Error(std::string("this generator has no GPU version; GPU generators: ") + kGpuGeneratorNames);
  if (fused && r.kind == DeviceRecipe::Kind::Grouping && r.order == RayOrder::Scanline)
    throw Error(
        "order=scanline has no fused form (a fused block makes one tile's rays); use order=tile or order=group, or "
        "cuda:pipeline=device");
  if (r.kind == DeviceRecipe::Kind::Grouping && r.tile_w * r.tile_h > kMaxGroupTile)
    throw Error("GPU generator: tile=" + std::to_string(r.tile_w) + "x" + std::to_string(r.tile_h) + " has " +
                std::to_string(r.tile_w * r.tile_h) + " pixels; the GPU version takes at most " +
                std::to_string(kMaxGroupTile) + " (one thread per pixel)");
  return r;
}

}  // namespace

void check_gpu_generator(const Generator& cpu, bool fused) { gpu_recipe(cpu, fused); }

struct DeviceGenerator::Impl {
  DeviceBuffer<BsdfParams> materials;
  DeviceBuffer<BsdfParams> hit_materials;  // a textured scene's G-buffer table (per frame)
  DeviceBuffer<ShadingPoint> points;
  DeviceBuffer<uint32_t> counts, offsets, flags, slots;
  DeviceBuffer<unsigned char> scan_temp;
  DeviceBatch batch;
  DeviceBuffer<unsigned long long> stats{kStatCount};
  EventTimer timer;
  float last_ms = -1.f;
  // The uploaded G-buffer's facts and the last launch's batch (device_batch()).
  const BsdfParams* point_materials = nullptr;
  const ShadingPoint* point_data = nullptr;  // the points launches read: points' own, or a device G-buffer's
  int width = 0, height = 0;
  uint32_t frame = 0;
  size_t hits = 0, tiles = 0;
  bool grouping = false, uploaded = false, launched = false;
  bool fused = false;  // the last launch was launch_fused without a batch (no batch, no tile offsets)
  BatchView view{};
  struct Plan;
  Plan plan(uint32_t seed, const Generator& cpu, bool fused) const;
  void start_batch(const Plan& p);

  // out[i] = sum of in[0 .. i) for i <= n (CUB's device-wide scan).
  void exclusive_sum(const uint32_t* in, uint32_t* out, size_t n) {
    if (n > 0x7fffffffu) throw Error("cuda: scan of " + std::to_string(n) + " items is too large");
    size_t bytes = 0;
    RAYCOH_CUDA_CHECK(cub::DeviceScan::ExclusiveSum(nullptr, bytes, in, out, static_cast<int>(n)));
    scan_temp.reserve(bytes);
    RAYCOH_CUDA_CHECK(cub::DeviceScan::ExclusiveSum(scan_temp.get(), bytes, in, out, static_cast<int>(n)));
  }

  // Buffers for n rays over `tiles` tiles of `pixels` pixels; the batch's columns as a view.
  BatchView reserve(size_t n, size_t pixels, size_t tiles, bool grouping, bool scanline) {
    counts.zero(tiles + 1);  // counts[tiles] = 0, so that offsets[tiles] = the total
    offsets.reserve(tiles + 1);
    stats.zero(kStatCount);
    if (scanline) {
      flags.reserve(pixels);
      slots.reserve(pixels);
    }
    return batch.reserve(n, grouping);
  }

  GenerationStats download_stats() const {
    unsigned long long s[kStatCount];
    stats.download(s, kStatCount);
    GenerationStats out;
    out.rays = s[kStatRays];
    out.below_geometric = s[kStatBelowGeometric];
    out.below_shading = s[kStatBelowShading];
    out.non_finite = s[kStatNonFinite];
    for (int t = 0; t < 5; ++t) out.groups[t] = s[kStatGroups + t];
    out.hybrid_mean_fallback = s[kStatHybridFallback];
    out.reused_rays = s[kStatReused];
    return out;
  }
};

DeviceGenerator::DeviceGenerator(const Scene& scene) : impl_(std::make_unique<Impl>()) {
  std::vector<BsdfParams> materials;
  materials.reserve(scene.materials.size());
  for (const Material& m : scene.materials) materials.push_back(bsdf_params(m));
  impl_->materials.upload(materials.data(), materials.size());
}

DeviceGenerator::~DeviceGenerator() = default;

float DeviceGenerator::last_kernel_ms() const { return impl_->last_ms; }

void DeviceGenerator::upload(const GBuffer& g) {
  Impl& m = *impl_;
  const size_t pixels = g.points.size();
  if (pixels != static_cast<size_t>(g.width) * static_cast<size_t>(g.height))
    throw Error("cuda: the G-buffer's size does not match its resolution");
  m.points.upload(g.points.data(), pixels);
  m.point_data = m.points.get();
  // A textured scene's points index the G-buffer's own table (the texels at each hit): it goes up with them.
  m.point_materials = m.materials.get();
  if (g.materials && g.materials->per_hit()) {
    m.hit_materials.upload(g.materials->bsdf.data(), g.materials->bsdf.size());
    m.point_materials = m.hit_materials.get();
  }
  m.width = g.width;
  m.height = g.height;
  m.frame = g.frame;
  m.hits = g.hits;
  m.uploaded = true;
}

void DeviceGenerator::use_device(const DeviceGBufferView& g) {
  Impl& m = *impl_;
  if (g.width < 1 || g.height < 1 || !g.points || !g.bsdf) throw Error("cuda: an empty device G-buffer");
  m.point_data = g.points;
  m.point_materials = g.bsdf;
  m.width = g.width;
  m.height = g.height;
  m.frame = g.frame;
  m.hits = g.hits;
  m.uploaded = true;
}

// What one launch generates: the CPU generator's typed configuration and the tile grid of its order.
struct DeviceGenerator::Impl::Plan {
  bool grouping = false, scanline = false;
  bool shared = false;  // sadeghi, microjitter: the per-pixel kernel with shared numbers
  GroupingConfig config{};
  SharedSampleConfig sharing{};
  TileGrid grid;
  size_t pixels = 0, tiles = 0;
};

DeviceGenerator::Impl::Plan DeviceGenerator::Impl::plan(uint32_t seed, const Generator& cpu, bool fused) const {
  if (!uploaded) throw Error("cuda: DeviceGenerator::launch before upload (no G-buffer on the device)");
  Plan p;
  const DeviceRecipe r = gpu_recipe(cpu, fused);
  p.grouping = r.kind == DeviceRecipe::Kind::Grouping;
  p.config = p.grouping ? r.config(seed, frame) : GroupingConfig{};
  p.shared = r.kind == DeviceRecipe::Kind::SharedSample;
  p.sharing = r.shared;
  // The per-pixel kernels' scanline order is their tile order with one-row tiles, as on the CPU.
  p.grid = !p.grouping && r.order == RayOrder::Scanline ? TileGrid(width, height, width, 1)
                                                        : TileGrid(width, height, r.tile_w, r.tile_h);
  p.pixels = static_cast<size_t>(width) * static_cast<size_t>(height);
  p.tiles = static_cast<size_t>(p.grid.count());
  p.scanline = p.grouping && p.config.order == RayOrder::Scanline;
  return p;
}

// The batch's buffers for the plan, and each tile's first slot (offsets) once the timer has started.
void DeviceGenerator::Impl::start_batch(const Plan& p) {
  view = reserve(hits, p.pixels, p.tiles, p.grouping, p.scanline);
  grouping = p.grouping;
  tiles = p.tiles;
  fused = false;
  timer.start();
  if (p.tiles == 0 || hits == 0) return;
  tile_hits_kernel<<<static_cast<unsigned>(p.tiles), 128>>>(point_data, p.grid, counts.get());
  RAYCOH_CUDA_CHECK_LAUNCH();
  exclusive_sum(counts.get(), offsets.get(), p.tiles + 1);
}

void DeviceGenerator::launch(uint32_t seed, const Generator& cpu) {
  Impl& m = *impl_;
  const Impl::Plan p = m.plan(seed, cpu, false);
  m.start_batch(p);
  if (p.tiles > 0 && m.hits > 0) {
    if (p.scanline) {
      hit_flags_kernel<<<blocks_for(p.pixels, 256), 256>>>(m.point_data, p.pixels, m.flags.get());
      RAYCOH_CUDA_CHECK_LAUNCH();
      m.exclusive_sum(m.flags.get(), m.slots.get(), p.pixels);
    }
    if (p.grouping) {
      launch_group_kernel(p.config, p.grid, m.point_data, m.point_materials, m.offsets.get(), m.slots.get(), m.view,
                          m.stats.get());
    } else if (p.shared) {
      const SharedNumbers numbers{p.sharing, !shared_sample_all_own(p.sharing, m.width, m.height)};
      launch_per_pixel_kernel(p.grid, m.point_data, m.point_materials, seed, m.frame, m.offsets.get(), m.view,
                              m.stats.get(), &numbers);
    } else {
      launch_per_pixel_kernel(p.grid, m.point_data, m.point_materials, seed, m.frame, m.offsets.get(), m.view,
                              m.stats.get(), nullptr);
    }
  }
  m.timer.stop();
  m.launched = true;
}

void DeviceGenerator::launch_fused(uint32_t seed, const Generator& cpu, const DeviceTracer& tracer,
                                   const TraceLaunch& trace, Hit* hits, bool keep_batch) {
  Impl& m = *impl_;
  const Impl::Plan p = m.plan(seed, cpu, true);
  FusedBatch batch;
  if (keep_batch) {
    m.start_batch(p);  // zeroes the statistics
    batch = FusedBatch{m.view, m.offsets.get()};
  } else {
    m.stats.zero(kStatCount);
    m.grouping = p.grouping;
    m.tiles = p.tiles;
    m.fused = true;
    m.view = BatchView{};
    m.timer.start();
  }
  const DeviceScene scene = tracer.device_scene();
  const SharedNumbers numbers{p.sharing, !shared_sample_all_own(p.sharing, m.width, m.height)};
  if (p.tiles > 0 && m.hits > 0) {
    if (p.grouping)
      launch_fused_grouping(scene, trace, p.config, p.grid, m.point_data, m.point_materials, batch, hits,
                            m.stats.get());
    else
      launch_fused_per_pixel(scene, trace, m.point_data, m.point_materials, seed, m.frame, p.grid, batch, hits,
                             m.stats.get(), p.shared ? &numbers : nullptr);
  }
  m.timer.stop();
  m.launched = true;
}

void DeviceGenerator::finish(GenerationStats& stats) {
  Impl& m = *impl_;
  if (!m.launched) throw Error("cuda: DeviceGenerator::finish without a launch");
  m.last_ms = m.timer.elapsed_ms();
  stats = m.download_stats();
  uint64_t total = stats.rays;  // the fused trace keeps no tile offsets: its ray count
  if (!m.fused && m.tiles > 0 && m.hits > 0) {
    uint32_t offsets_total = 0;
    RAYCOH_CUDA_CHECK(cudaMemcpy(&offsets_total, m.offsets.get() + m.tiles, sizeof(uint32_t), cudaMemcpyDeviceToHost));
    total = offsets_total;
  }
  if (total != m.hits)
    throw Error("cuda: the device counted " + std::to_string(total) + " hit pixels, the G-buffer " +
                std::to_string(m.hits));
}

BatchView DeviceGenerator::device_batch() const { return impl_->view; }

namespace {
__global__ void hybrid_diffuse_kernel(const GroupType* group_type, const MaterialClass* material, size_t n,
                                      unsigned long long* count) {
  const size_t i = static_cast<size_t>(blockIdx.x) * blockDim.x + threadIdx.x;
  const unsigned lanes = __ballot_sync(0xffffffffu, i < n && is_hybrid_diffuse(group_type[i], material[i]));
  if ((threadIdx.x & 31) == 0 && lanes) atomicAdd(count, static_cast<unsigned long long>(__popc(lanes)));
}
}  // namespace

uint64_t DeviceGenerator::count_hybrid_diffuse() const {
  const Impl& m = *impl_;
  if (!m.grouping || m.fused || m.hits == 0 || !m.view.group_type) return 0;
  DeviceBuffer<unsigned long long> count;
  count.zero(1);
  hybrid_diffuse_kernel<<<blocks_for(m.hits, 256), 256>>>(m.view.group_type, m.view.material, m.hits, count.get());
  RAYCOH_CUDA_CHECK_LAUNCH();
  unsigned long long n = 0;
  count.download(&n, 1);
  return n;
}

size_t DeviceGenerator::device_count() const { return impl_->hits; }

void DeviceGenerator::download(RayBatch& out) const {
  const Impl& m = *impl_;
  out.width = m.width;
  out.height = m.height;
  out.frame = m.frame;
  m.batch.download(out, m.hits, m.grouping);
}

void DeviceGenerator::generate(const GBuffer& g, uint32_t seed, const Generator& cpu, RayBatch& out,
                               GenerationStats& stats) {
  upload(g);
  launch(seed, cpu);
  finish(stats);
  download(out);
}

}  // namespace raycoh::cuda
