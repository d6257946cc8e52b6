// Primary rays and the noopt / ours / tile generators on the GPU (cuda/device_generators.h explains the method;
// generators/noopt.cpp and generators/tangent_reuse.cpp are the CPU versions these kernels must equal byte for
// byte). The per-ray math is the shared host/device code (core/bsdf.h sample_direction / diffuse_from_local,
// core/secondary_ray.h, core/tile_shuffle.h, core/sampling.h, core/rng.h); what the CPU does in host-only
// helpers is restated here in device code, line for line, and pinned by the gpu-labelled tests
// (tests/gpu_generators_test.cpp):
//   TileGrid::rect (tiles.cpp)                 -> Grid::rect
//   make_primary_rays' per-pixel expression    -> primary_kernel
// Liu et al., "Generate Coherent Rays Directly" (Eurographics 2024), sections 3.2-3.3, is the method of `ours`.
// (No fmt here: its consteval format strings do not compile under nvcc 13.)
#include <cuda_runtime.h>

#include <cmath>
#include <cub/device/device_scan.cuh>
#include <string>

#include "core/bsdf.h"
#include "core/error.h"
#include "core/params.h"
#include "core/rng.h"
#include "core/secondary_ray.h"
#include "core/tile_shuffle.h"
#include "cuda/cuda_check.cuh"
#include "cuda/device_generators.h"
#include "generators/generator.h"

namespace raycoh::cuda {

namespace {

constexpr unsigned kFullMask = 0xffffffffu;
constexpr int kMaxGroupTile = 1024;  // ours / tile: one thread per pixel of a tile

// Statistics slots on the device (GenerationStats, in this order).
enum StatSlot : int {
  kStatRays = 0,
  kStatBelowGeometric = 1,
  kStatBelowShading = 2,
  kStatNonFinite = 3,
  kStatGroups = 4,  // 4 .. 8, indexed by GroupType
  kStatHybridFallback = 9,
  kStatReused = 10,
  kStatCount = 11,
};

// The batch's arrays on the device.
struct BatchView {
  Ray* rays;
  uint32_t* pixel;
  float* pdf;
  Vec3* weight;
  Vec3* normal;
  MaterialClass* material;
  uint32_t* tile;  // null for generators without groups
  uint32_t* group;
  GroupType* group_type;
};

// TileGrid of generators/tiles.h.
struct Grid {
  int width, height, tile_w, tile_h, tiles_x, tiles_y;
  __device__ void rect(int t, int& x0, int& y0, int& w, int& h) const {
    x0 = (t % tiles_x) * tile_w;
    y0 = (t / tiles_x) * tile_h;
    w = min(tile_w, width - x0);
    h = min(tile_h, height - y0);
  }
  int count() const { return tiles_x * tiles_y; }
};

Grid make_grid(int width, int height, int tile_w, int tile_h) {
  return Grid{width, height, tile_w, tile_h, (width + tile_w - 1) / tile_w, (height + tile_h - 1) / tile_h};
}

__device__ __forceinline__ bool is_hit(const ShadingPoint& sp) { return sp.prim != kNoHit; }
__device__ __forceinline__ bool is_diffuse_like(MaterialClass c) {
  return c == MaterialClass::Diffuse || c == MaterialClass::Emissive;
}
__device__ __forceinline__ bool is_glossy_like(MaterialClass c) {
  return c == MaterialClass::Glossy || c == MaterialClass::Specular;
}

// Ray `slot` from a shading point and its direction sample (core/secondary_ray.h, as the CPU's emit_ray);
// returns the flags.
__device__ uint32_t write_ray(const BatchView& out, uint32_t slot, const ShadingPoint& sp, uint32_t pixel,
                              const DirectionSample& s) {
  const SecondaryRay r = make_secondary_ray(sp.position, sp.ng, sp.ns, s);
  out.rays[slot] = r.ray;
  out.weight[slot] = r.weight;
  out.normal[slot] = r.normal;
  out.pixel[slot] = pixel;
  out.pdf[slot] = s.pdf;
  out.material[slot] = sp.cls;
  return r.flags;
}

// Exclusive count of `flag` over the block's threads in thread order, and the block's total. Every thread of the
// block calls it (blockDim.x a multiple of 32); warp_totals is __shared__ uint32_t[32].
__device__ uint32_t block_exclusive_count(bool flag, uint32_t* warp_totals, uint32_t& total) {
  const unsigned lane = threadIdx.x & 31u, warp = threadIdx.x >> 5;
  const unsigned bits = __ballot_sync(kFullMask, flag);
  if (lane == 0) warp_totals[warp] = static_cast<uint32_t>(__popc(bits));
  __syncthreads();
  uint32_t before = 0;
  total = 0;
  for (unsigned w = 0; w < (blockDim.x >> 5); ++w) {
    const uint32_t v = warp_totals[w];
    if (w < warp) before += v;
    total += v;
  }
  __syncthreads();  // warp_totals may be rewritten by the next call
  return before + static_cast<uint32_t>(__popc(bits & ((1u << lane) - 1u)));
}

// Adds each thread's tallies of emitted rays into the statistics (one atomic per counter and block).
__device__ void tally_block(bool emitted, uint32_t flags, unsigned long long* stats) {
  const int rays = __syncthreads_count(emitted);
  const int below_geometric = __syncthreads_count(emitted && (flags & kSampleBelowGeometric));
  const int below_shading = __syncthreads_count(emitted && (flags & kSampleBelowShading));
  const int non_finite = __syncthreads_count(emitted && (flags & kSampleNonFinite));
  if (threadIdx.x == 0) {
    if (rays) atomicAdd(stats + kStatRays, static_cast<unsigned long long>(rays));
    if (below_geometric) atomicAdd(stats + kStatBelowGeometric, static_cast<unsigned long long>(below_geometric));
    if (below_shading) atomicAdd(stats + kStatBelowShading, static_cast<unsigned long long>(below_shading));
    if (non_finite) atomicAdd(stats + kStatNonFinite, static_cast<unsigned long long>(non_finite));
  }
}

// ---- primary rays -----------------------------------------------------------------------------------------------

struct PrimaryParams {
  Vec3 eye, forward, right, up;
  float tan_half, aspect;
  int width, height, tile_w, tile_h;
  bool tile_order, jitter;
  uint32_t seed, frame;
};

__global__ void primary_kernel(PrimaryParams pp, Ray* rays, uint32_t* pixels) {
  const size_t n = static_cast<size_t>(pp.width) * static_cast<size_t>(pp.height);
  const size_t index = blockIdx.x * static_cast<size_t>(blockDim.x) + threadIdx.x;
  if (index >= n) return;
  const auto p = static_cast<uint32_t>(index);
  const auto width = static_cast<uint32_t>(pp.width);
  size_t slot = p;
  if (pp.tile_order) {  // make_pixel_order's tile order, inverted
    const int x = static_cast<int>(p % width), y = static_cast<int>(p / width);
    const int row0 = (y / pp.tile_h) * pp.tile_h, col0 = (x / pp.tile_w) * pp.tile_w;
    const int h = min(pp.tile_h, pp.height - row0), w = min(pp.tile_w, pp.width - col0);
    slot = static_cast<size_t>(row0) * pp.width + static_cast<size_t>(col0) * h + static_cast<size_t>(y - row0) * w +
           static_cast<size_t>(x - col0);
  }
  const float jx = pp.jitter ? rng_float(pp.seed, pp.frame, p, kDimPixelJitterX) : 0.5f;
  const float jy = pp.jitter ? rng_float(pp.seed, pp.frame, p, kDimPixelJitterY) : 0.5f;
  const float sx =
      (2.f * ((static_cast<float>(p % width) + jx) / static_cast<float>(pp.width)) - 1.f) * pp.tan_half * pp.aspect;
  const float sy = (1.f - 2.f * ((static_cast<float>(p / width) + jy) / static_cast<float>(pp.height))) * pp.tan_half;
  Ray ray;
  ray.org = pp.eye;
  ray.dir = normalize(pp.forward + pp.right * sx + pp.up * sy);
  ray.tmin = 0.f;
  ray.tmax = __builtin_huge_valf();
  rays[slot] = ray;
  pixels[slot] = p;
}

__global__ void sincos_kernel(const float* u, size_t n, float* s, float* c) {
  const size_t i = blockIdx.x * static_cast<size_t>(blockDim.x) + threadIdx.x;
  if (i < n) sincos_turns(u[i], s[i], c[i]);
}

// ---- tile offsets -----------------------------------------------------------------------------------------------

// counts[t] = hit pixels of tile t (one block per tile).
__global__ void tile_hits_kernel(const ShadingPoint* points, Grid grid, uint32_t* counts) {
  const int t = blockIdx.x;
  int x0, y0, w, h;
  grid.rect(t, x0, y0, w, h);
  const int m = w * h;
  int hits = 0;
  for (int base = 0; base < m; base += blockDim.x) {
    const int i = base + static_cast<int>(threadIdx.x);
    const bool hit = i < m && is_hit(points[static_cast<size_t>(y0 + i / w) * grid.width + x0 + i % w]);
    hits += __syncthreads_count(hit);
  }
  if (threadIdx.x == 0) counts[t] = static_cast<uint32_t>(hits);
}

// flags[p] = 1 for hit pixels (scanline slots).
__global__ void hit_flags_kernel(const ShadingPoint* points, size_t n, uint32_t* flags) {
  const size_t p = blockIdx.x * static_cast<size_t>(blockDim.x) + threadIdx.x;
  if (p < n) flags[p] = is_hit(points[p]) ? 1u : 0u;
}

// ---- noopt ------------------------------------------------------------------------------------------------------

__global__ void noopt_kernel(const ShadingPoint* points, const BsdfParams* materials, uint32_t seed, uint32_t frame,
                             Grid grid, const uint32_t* offsets, BatchView out, unsigned long long* stats) {
  __shared__ uint32_t warp_totals[32];
  const int t = blockIdx.x;
  int x0, y0, w, h;
  grid.rect(t, x0, y0, w, h);
  const int m = w * h;
  uint32_t next = offsets[t];
  // Tallies of this thread's rays (a thread may write several in a large tile).
  uint32_t rays = 0, below_geometric = 0, below_shading = 0, non_finite = 0;
  for (int base = 0; base < m; base += blockDim.x) {
    const int i = base + static_cast<int>(threadIdx.x);
    const auto p = static_cast<uint32_t>(i < m ? (y0 + i / w) * grid.width + x0 + i % w : 0);
    const bool hit = i < m && is_hit(points[p]);
    uint32_t total;
    const uint32_t rank = block_exclusive_count(hit, warp_totals, total);
    if (hit) {
      const ShadingPoint& sp = points[p];
      const DirectionSample s = sample_direction(
          materials[sp.material], sp.ns, sp.ng, sp.wo, sp.front_face, rng_float(seed, frame, p, kDimSecondary0),
          rng_float(seed, frame, p, kDimSecondary1), rng_float(seed, frame, p, kDimSecondaryLobe));
      const uint32_t flags = write_ray(out, next + rank, sp, p, s);
      ++rays;
      below_geometric += (flags & kSampleBelowGeometric) != 0;
      below_shading += (flags & kSampleBelowShading) != 0;
      non_finite += (flags & kSampleNonFinite) != 0;
    }
    next += total;
  }
  // Few rays per block: shared-memory sums, then one global atomic per counter.
  __shared__ unsigned long long sums[4];
  if (threadIdx.x < 4) sums[threadIdx.x] = 0;
  __syncthreads();
  if (rays) atomicAdd(&sums[0], static_cast<unsigned long long>(rays));
  if (below_geometric) atomicAdd(&sums[1], static_cast<unsigned long long>(below_geometric));
  if (below_shading) atomicAdd(&sums[2], static_cast<unsigned long long>(below_shading));
  if (non_finite) atomicAdd(&sums[3], static_cast<unsigned long long>(non_finite));
  __syncthreads();
  if (threadIdx.x < 4 && sums[threadIdx.x]) atomicAdd(stats + kStatRays + threadIdx.x, sums[threadIdx.x]);
}

// ---- ours / tile ------------------------------------------------------------------------------------------------

struct GroupParams {
  uint32_t seed, group_seed, frame, k, groups_per_full_tile;
  bool interleaved, group_order, scanline;
};

enum PixelFlag : uint32_t { kPixelHit = 1u, kPixelDiffuse = 2u, kPixelGlossy = 4u, kPixelMeanOk = 8u };

// Dynamic shared memory of one tile of m pixels and up to g groups.
struct TileShared {
  uint32_t* group_of;  // [m] group in tile of pixel number i
  uint32_t* flags;     // [m] PixelFlag bits
  uint32_t* pos;       // [m] position of a hit pixel among its tile's hits, group by group
  Vec3* local;         // [m] glossy member's tangent-space direction (valid when kPixelMeanOk)
  uint32_t* count;     // [g] hit members
  uint32_t* diffuse;   // [g] diffuse-like members
  uint32_t* glossy;    // [g] glossy-like members
  uint32_t* start;     // [g] first position of the group
  uint32_t* donor;     // [g] pixel (image index) of the donor
  uint32_t* type;      // [g] GroupType
  Vec3* shared_dir;    // [g] tangent-space direction of the diffuse members
};

__host__ __device__ size_t tile_shared_bytes(uint32_t m, uint32_t g) {
  return static_cast<size_t>(m) * (3 * sizeof(uint32_t) + sizeof(Vec3)) +
         static_cast<size_t>(g) * (6 * sizeof(uint32_t) + sizeof(Vec3));
}

__device__ TileShared carve_tile_shared(unsigned char* base, uint32_t m, uint32_t g) {
  TileShared s;
  auto take_u32 = [&base](uint32_t n) {
    auto* p = reinterpret_cast<uint32_t*>(base);
    base += sizeof(uint32_t) * n;
    return p;
  };
  auto take_vec = [&base](uint32_t n) {
    auto* p = reinterpret_cast<Vec3*>(base);
    base += sizeof(Vec3) * n;
    return p;
  };
  s.group_of = take_u32(m);
  s.flags = take_u32(m);
  s.pos = take_u32(m);
  s.count = take_u32(g);
  s.diffuse = take_u32(g);
  s.glossy = take_u32(g);
  s.start = take_u32(g);
  s.donor = take_u32(g);
  s.type = take_u32(g);
  s.local = take_vec(m);
  s.shared_dir = take_vec(g);
  return s;
}

// One block per tile, one thread per pixel number i of the tile (blockDim.x >= the full tile's area).
__global__ void group_kernel(const ShadingPoint* points, const BsdfParams* materials, GroupParams gp, Grid grid,
                             const uint32_t* offsets, const uint32_t* scanline_slots, BatchView out,
                             unsigned long long* stats) {
  extern __shared__ unsigned char shared_bytes[];
  __shared__ uint32_t warp_totals[32];
  const int t = blockIdx.x;
  int x0, y0, w, h;
  grid.rect(t, x0, y0, w, h);
  const auto m = static_cast<uint32_t>(w * h);
  const uint32_t groups = (m + gp.k - 1) / gp.k;
  const uint32_t full_m = static_cast<uint32_t>(grid.tile_w * grid.tile_h);
  const TileShared sh = carve_tile_shared(shared_bytes, full_m, (full_m + gp.k - 1) / gp.k);
  auto pixel_of = [&](uint32_t i) {
    return static_cast<uint32_t>((y0 + static_cast<int>(i) / w) * grid.width + x0 + static_cast<int>(i) % w);
  };

  // Phase 1 (pixel i): group, flags, rank among the tile's hits in row-major order.
  const uint32_t i = threadIdx.x;
  const bool in_tile = i < m;
  const uint32_t p = in_tile ? pixel_of(i) : 0u;
  const bool hit = in_tile && is_hit(points[p]);
  const MaterialClass cls = hit ? points[p].cls : MaterialClass::Diffuse;
  if (in_tile) {
    const TileShuffle shuffle = make_tile_shuffle(m, gp.group_seed, gp.frame, static_cast<uint32_t>(t));
    sh.group_of[i] = (gp.interleaved ? shuffle(i) : i) / gp.k;
    sh.flags[i] = (hit ? kPixelHit : 0u) | (hit && is_diffuse_like(cls) ? kPixelDiffuse : 0u) |
                  (hit && is_glossy_like(cls) ? kPixelGlossy : 0u);
  }
  uint32_t hits;
  const uint32_t rank = block_exclusive_count(hit, warp_totals, hits);  // also publishes group_of and flags
  if (hits == 0) return;                                                // the same for the whole block

  // Phase 2 (group q): members, classification.
  const uint32_t q = threadIdx.x;
  if (q < groups) {
    uint32_t count = 0, diffuse = 0, glossy = 0;
    for (uint32_t j = 0; j < m; ++j) {
      if (sh.group_of[j] != q || !(sh.flags[j] & kPixelHit)) continue;
      ++count;
      diffuse += (sh.flags[j] & kPixelDiffuse) != 0;
      glossy += (sh.flags[j] & kPixelGlossy) != 0;
    }
    const GroupType type = diffuse && glossy ? GroupType::Hybrid
                           : diffuse         ? GroupType::Diffuse
                           : glossy          ? GroupType::Glossy
                                             : GroupType::Independent;
    sh.count[q] = count;
    sh.diffuse[q] = diffuse;
    sh.glossy[q] = glossy;
    sh.type[q] = static_cast<uint32_t>(type);
    if (count > 0) atomicAdd(stats + kStatGroups + static_cast<int>(type), 1ull);
  }
  __syncthreads();
  // Phase 3: first position of each group (a scan over few groups).
  if (threadIdx.x == 0) {
    uint32_t s = 0;
    for (uint32_t g = 0; g < groups; ++g) {
      sh.start[g] = s;
      s += sh.count[g];
    }
  }
  __syncthreads();
  // Phase 4 (group q): member positions in row-major order, and the donor (the d-th diffuse member).
  if (q < groups && sh.count[q] > 0) {
    const uint32_t group_id = static_cast<uint32_t>(t) * gp.groups_per_full_tile + q;
    const uint32_t n_diffuse = sh.diffuse[q];
    uint32_t d = n_diffuse <= 1 ? 0u : rng_u32(gp.group_seed, gp.frame, group_id, kDimGroupDonor) % n_diffuse;
    uint32_t position = sh.start[q], donor = 0;
    bool found = false;
    for (uint32_t j = 0; j < m; ++j) {
      if (sh.group_of[j] != q || !(sh.flags[j] & kPixelHit)) continue;
      sh.pos[j] = position++;
      if (!found && (sh.flags[j] & kPixelDiffuse) && d-- == 0) {
        donor = pixel_of(j);
        found = true;
      }
    }
    sh.donor[q] = donor;
  }
  __syncthreads();

  const uint32_t my_group = in_tile ? sh.group_of[i] : 0u;
  const uint32_t group_id = static_cast<uint32_t>(t) * gp.groups_per_full_tile + my_group;
  const uint32_t slot = gp.scanline ? scanline_slots[p] : offsets[t] + (gp.group_order ? (hit ? sh.pos[i] : 0u) : rank);
  bool emitted = false;
  uint32_t emitted_flags = 0;
  auto emit = [&](const DirectionSample& s) {
    emitted_flags = write_ray(out, slot, points[p], p, s);
    emitted = true;
    out.tile[slot] = static_cast<uint32_t>(t);
    out.group[slot] = group_id;
    out.group_type[slot] = static_cast<GroupType>(sh.type[my_group]);
  };

  // Phase 5 (pixel i): glossy and transmissive members sample their own lobes with NoOpt's random numbers.
  if (hit && !is_diffuse_like(cls)) {
    const ShadingPoint& sp = points[p];
    const DirectionSample s = sample_direction(
        materials[sp.material], sp.ns, sp.ng, sp.wo, sp.front_face, rng_float(gp.seed, gp.frame, p, kDimSecondary0),
        rng_float(gp.seed, gp.frame, p, kDimSecondary1), rng_float(gp.seed, gp.frame, p, kDimSecondaryLobe));
    emit(s);
    if (is_glossy_like(cls) && s.flags == kSampleOk) {
      const Vec3 local = make_frame(sp.ns).to_local(s.dir);
      if (local.z > 0.f) {
        sh.local[i] = local;
        sh.flags[i] |= kPixelMeanOk;
      }
    }
  }
  __syncthreads();
  // Phase 6 (group q): the diffuse members' direction: the glossy mean (hybrid groups, summed in row-major
  // order as the CPU does) or the donor's cosine sample.
  if (q < groups && sh.count[q] > 0 && sh.diffuse[q] > 0) {
    const auto type = static_cast<GroupType>(sh.type[q]);
    Vec3 mean{0.f, 0.f, 0.f};
    uint32_t n_mean = 0;
    for (uint32_t j = 0; j < m; ++j) {
      if (sh.group_of[j] != q || !(sh.flags[j] & kPixelMeanOk)) continue;
      mean += sh.local[j];
      ++n_mean;
    }
    const float mean_len = length(mean);
    bool from_donor = false;
    if (type == GroupType::Hybrid && n_mean > 0 && mean_len > 1e-2f * static_cast<float>(n_mean) && mean.z > 0.f) {
      sh.shared_dir[q] = mean * (1.f / mean_len);
    } else {
      if (type == GroupType::Hybrid) atomicAdd(stats + kStatHybridFallback, 1ull);
      const uint32_t donor = sh.donor[q];
      sh.shared_dir[q] = sample_cosine_hemisphere(rng_float(gp.seed, gp.frame, donor, kDimSecondary0),
                                                  rng_float(gp.seed, gp.frame, donor, kDimSecondary1));
      from_donor = true;
    }
    atomicAdd(stats + kStatReused, static_cast<unsigned long long>(sh.diffuse[q] - (from_donor ? 1u : 0u)));
  }
  __syncthreads();
  // Phase 7 (pixel i): diffuse members use the group's tangent-space direction in their own frame.
  if (hit && is_diffuse_like(cls)) {
    const ShadingPoint& sp = points[p];
    emit(diffuse_from_local(materials[sp.material], sp.ns, sp.ng, sh.shared_dir[my_group]));
  }
  tally_block(emitted, emitted_flags, stats);
}

unsigned blocks_for(size_t n, int block) {
  const size_t blocks = (n + static_cast<size_t>(block) - 1) / static_cast<size_t>(block);
  if (blocks > 0x7fffffffu) throw Error("cuda: " + std::to_string(n) + " threads are too many for one launch");
  return static_cast<unsigned>(blocks);
}

int round_up_warp(int n) { return (n + 31) / 32 * 32; }

}  // namespace

// ---- host side --------------------------------------------------------------------------------------------------

void make_primary_rays_gpu(const Camera& camera, int width, int height, RayOrder order, int tile_w, int tile_h,
                           uint32_t seed, uint32_t frame, bool jitter, PrimaryBatch& out, float* kernel_ms) {
  if (width < 1 || height < 1 || tile_w < 1 || tile_h < 1)
    throw Error("cuda: primary rays need a positive resolution and tile size");
  PrimaryParams pp;
  // The same host arithmetic as make_primary_rays (generators/primary.cpp).
  pp.eye = camera.eye;
  pp.forward = normalize(camera.target - camera.eye);
  pp.right = normalize(cross(pp.forward, camera.up));
  pp.up = cross(pp.right, pp.forward);
  pp.tan_half = std::tan(camera.vfov_deg * 0.5f * kPi / 180.f);
  pp.aspect = static_cast<float>(width) / static_cast<float>(height);
  pp.width = width;
  pp.height = height;
  pp.tile_w = tile_w;
  pp.tile_h = tile_h;
  pp.tile_order = order == RayOrder::Tile;
  pp.jitter = jitter;
  pp.seed = seed;
  pp.frame = frame;

  const size_t n = static_cast<size_t>(width) * static_cast<size_t>(height);
  DeviceBuffer<Ray> rays(n);
  DeviceBuffer<uint32_t> pixels(n);
  EventTimer timer;
  timer.start();
  primary_kernel<<<blocks_for(n, 256), 256>>>(pp, rays.get(), pixels.get());
  RAYCOH_CUDA_CHECK_LAUNCH();
  timer.stop();
  const float ms = timer.elapsed_ms();
  if (kernel_ms) *kernel_ms = ms;
  out.width = width;
  out.height = height;
  out.frame = frame;
  out.rays.resize(n);
  out.pixel.resize(n);
  rays.download(out.rays.data(), n);
  pixels.download(out.pixel.data(), n);
}

void sincos_turns_gpu(const float* u, size_t n, float* s, float* c) {
  DeviceBuffer<float> du, ds(n), dc(n);
  du.upload(u, n);
  if (n > 0) {
    sincos_kernel<<<blocks_for(n, 256), 256>>>(du.get(), n, ds.get(), dc.get());
    RAYCOH_CUDA_CHECK_LAUNCH();
  }
  ds.download(s, n);
  dc.download(c, n);
}

GpuGeneratorConfig gpu_generator_config(const std::string& name, const std::string& params) {
  GpuGeneratorConfig c;
  ParamSet set("generator '" + name + "' (GPU)", params);
  if (name == "noopt") {
    c.kind = GpuGeneratorKind::NoOpt;
    c.order =
        set.get_choice("order", "tile", {"scanline", "tile"}) == "tile" ? GpuBatchOrder::Tile : GpuBatchOrder::Scanline;
    const auto tile = set.get_size("tile", {8, 8}, 1, 4096);
    c.tile_w = tile.first;
    c.tile_h = tile.second;
  } else if (name == "ours" || name == "tile") {
    c.kind = name == "ours" ? GpuGeneratorKind::Ours : GpuGeneratorKind::Tile;
    const auto tile = set.get_size("tile", {8, 8}, 1, 1024);
    c.tile_w = tile.first;
    c.tile_h = tile.second;
    if (c.tile_w * c.tile_h > kMaxGroupTile)
      throw Error(set.owner() + ": tile=" + std::to_string(c.tile_w) + "x" + std::to_string(c.tile_h) + " has " +
                  std::to_string(c.tile_w * c.tile_h) + " pixels; the GPU version takes at most " +
                  std::to_string(kMaxGroupTile) + " (one thread per pixel)");
    c.k = set.get_int("k", 8, 1, c.tile_w * c.tile_h);
    const std::string order = set.get_choice("order", "tile", {"tile", "group", "scanline"});
    c.order = order == "tile" ? GpuBatchOrder::Tile : order == "group" ? GpuBatchOrder::Group : GpuBatchOrder::Scanline;
    c.salt = set.get_uint("seed", 0u, 0u, 0xFFFFFFFFu);
  } else {
    throw Error("generator '" + name + "' has no GPU version; GPU generators: noopt, ours, tile");
  }
  set.finish();
  return c;
}

struct DeviceGenerator::Impl {
  DeviceBuffer<BsdfParams> materials;
  DeviceBuffer<ShadingPoint> points;
  DeviceBuffer<uint32_t> counts, offsets, flags, slots;
  DeviceBuffer<unsigned char> scan_temp;
  DeviceBuffer<Ray> rays;
  DeviceBuffer<uint32_t> pixel;
  DeviceBuffer<float> pdf;
  DeviceBuffer<Vec3> weight, normal;
  DeviceBuffer<MaterialClass> material;
  DeviceBuffer<uint32_t> tile, group;
  DeviceBuffer<GroupType> group_type;
  DeviceBuffer<unsigned long long> stats{kStatCount};
  EventTimer timer;
  float last_ms = -1.f;

  // out[i] = sum of in[0 .. i) for i <= n (CUB's device-wide scan).
  void exclusive_sum(const uint32_t* in, uint32_t* out, size_t n) {
    if (n > 0x7fffffffu) throw Error("cuda: scan of " + std::to_string(n) + " items is too large");
    size_t bytes = 0;
    RAYCOH_CUDA_CHECK(cub::DeviceScan::ExclusiveSum(nullptr, bytes, in, out, static_cast<int>(n)));
    scan_temp.reserve(bytes);
    RAYCOH_CUDA_CHECK(cub::DeviceScan::ExclusiveSum(scan_temp.get(), bytes, in, out, static_cast<int>(n)));
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

void DeviceGenerator::generate(const GBuffer& g, uint32_t seed, const GpuGeneratorConfig& config, RayBatch& out,
                               GenerationStats& stats) {
  Impl& m = *impl_;
  const size_t pixels = g.points.size();
  if (pixels != static_cast<size_t>(g.width) * static_cast<size_t>(g.height))
    throw Error("cuda: the G-buffer's size does not match its resolution");
  const bool grouping = config.kind != GpuGeneratorKind::NoOpt;
  // NoOpt's scanline order is its tile order with one-row tiles, as on the CPU.
  const Grid grid = !grouping && config.order == GpuBatchOrder::Scanline
                        ? make_grid(g.width, g.height, g.width, 1)
                        : make_grid(g.width, g.height, config.tile_w, config.tile_h);
  const size_t tiles = static_cast<size_t>(grid.count());
  const size_t n = g.hits;

  m.points.upload(g.points.data(), pixels);
  m.counts.zero(tiles + 1);  // counts[tiles] = 0, so that offsets[tiles] = the total
  m.offsets.reserve(tiles + 1);
  m.rays.reserve(n);
  m.pixel.reserve(n);
  m.pdf.reserve(n);
  m.weight.reserve(n);
  m.normal.reserve(n);
  m.material.reserve(n);
  m.tile.reserve(n);
  m.group.reserve(n);
  m.group_type.reserve(n);
  m.stats.zero(kStatCount);
  const bool scanline = grouping && config.order == GpuBatchOrder::Scanline;
  if (scanline) {
    m.flags.reserve(pixels);
    m.slots.reserve(pixels);
  }
  const BatchView view{m.rays.get(),
                       m.pixel.get(),
                       m.pdf.get(),
                       m.weight.get(),
                       m.normal.get(),
                       m.material.get(),
                       grouping ? m.tile.get() : nullptr,
                       grouping ? m.group.get() : nullptr,
                       grouping ? m.group_type.get() : nullptr};

  GroupParams gp{};
  int group_block = 32;
  size_t group_shared = 0;
  if (grouping) {
    const auto full_m = static_cast<uint32_t>(config.tile_w * config.tile_h);
    if (full_m > static_cast<uint32_t>(kMaxGroupTile) || config.k < 1)
      throw Error("cuda: GPU grouping needs tiles of at most 1024 pixels and k >= 1");
    gp.seed = seed;
    gp.group_seed = seed ^ hash32(config.salt);
    gp.frame = g.frame;
    gp.k = static_cast<uint32_t>(config.k);
    gp.groups_per_full_tile = (full_m + gp.k - 1) / gp.k;
    gp.interleaved = config.kind == GpuGeneratorKind::Ours;
    gp.group_order = config.order == GpuBatchOrder::Group;
    gp.scanline = scanline;
    group_block = round_up_warp(static_cast<int>(full_m));
    group_shared = tile_shared_bytes(full_m, gp.groups_per_full_tile);
    if (group_shared > 48 * 1024)
      RAYCOH_CUDA_CHECK(cudaFuncSetAttribute(group_kernel, cudaFuncAttributeMaxDynamicSharedMemorySize,
                                             static_cast<int>(group_shared)));
  }

  m.timer.start();
  if (tiles > 0 && n > 0) {
    tile_hits_kernel<<<static_cast<unsigned>(tiles), 128>>>(m.points.get(), grid, m.counts.get());
    RAYCOH_CUDA_CHECK_LAUNCH();
    m.exclusive_sum(m.counts.get(), m.offsets.get(), tiles + 1);
    if (scanline) {
      hit_flags_kernel<<<blocks_for(pixels, 256), 256>>>(m.points.get(), pixels, m.flags.get());
      RAYCOH_CUDA_CHECK_LAUNCH();
      m.exclusive_sum(m.flags.get(), m.slots.get(), pixels);
    }
    if (grouping) {
      group_kernel<<<static_cast<unsigned>(tiles), group_block, group_shared>>>(
          m.points.get(), m.materials.get(), gp, grid, m.offsets.get(), m.slots.get(), view, m.stats.get());
    } else {
      const int block = std::min(256, round_up_warp(grid.tile_w * grid.tile_h));
      noopt_kernel<<<static_cast<unsigned>(tiles), block>>>(m.points.get(), m.materials.get(), seed, g.frame, grid,
                                                            m.offsets.get(), view, m.stats.get());
    }
    RAYCOH_CUDA_CHECK_LAUNCH();
  }
  m.timer.stop();
  m.last_ms = m.timer.elapsed_ms();

  uint32_t total = 0;
  if (tiles > 0 && n > 0)
    RAYCOH_CUDA_CHECK(cudaMemcpy(&total, m.offsets.get() + tiles, sizeof(uint32_t), cudaMemcpyDeviceToHost));
  if (total != n)
    throw Error("cuda: the device counted " + std::to_string(total) + " hit pixels, the G-buffer " + std::to_string(n));

  out.width = g.width;
  out.height = g.height;
  out.frame = g.frame;
  out.resize(n, grouping);
  m.rays.download(out.rays.data(), n);
  m.pixel.download(out.pixel.data(), n);
  m.pdf.download(out.pdf.data(), n);
  m.weight.download(out.weight.data(), n);
  m.normal.download(out.normal.data(), n);
  m.material.download(out.material.data(), n);
  if (grouping) {
    m.tile.download(out.tile.data(), n);
    m.group.download(out.group.data(), n);
    m.group_type.download(out.group_type.data(), n);
  }
  unsigned long long s[kStatCount];
  m.stats.download(s, kStatCount);
  stats = GenerationStats{};
  stats.rays = s[kStatRays];
  stats.below_geometric = s[kStatBelowGeometric];
  stats.below_shading = s[kStatBelowShading];
  stats.non_finite = s[kStatNonFinite];
  for (int t = 0; t < 5; ++t) stats.groups[t] = s[kStatGroups + t];
  stats.hybrid_mean_fallback = s[kStatHybridFallback];
  stats.reused_rays = s[kStatReused];
}

}  // namespace raycoh::cuda
