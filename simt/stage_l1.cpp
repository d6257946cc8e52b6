// The stage model's L1/TEX term; see stage_l1.h and docs/simt-model.md section 3.
#include "simt/stage_l1.h"

#include <algorithm>
#include <cmath>
#include <iterator>

#include "core/tile_grid.h"
#include "simt/stage_model.h"
#include "simt/warp_trace.h"

namespace raycoh {
namespace {

constexpr uint32_t kLanes = 32;
constexpr uint32_t kSampleTiles = 32;

uint32_t distinct(uint64_t* v, uint32_t n) {
  std::sort(v, v + n);
  return static_cast<uint32_t>(std::unique(v, v + n) - v);
}

// The lanes' addresses of the i-th instruction of row `a` in warp `k` of tile `rect` (pixel numbers from `first`).
uint32_t lane_addresses(const L1Access& a, uint32_t i, const TileRect& rect, int image_width, uint32_t first,
                        uint64_t warp, uint64_t* addr) {
  const uint32_t m = rect.area(), n = std::min(kLanes, m - first);
  const uint64_t offset = a.offset + (a.stride > a.offset ? uint64_t{i} * a.width % (a.stride - a.offset) : 0);
  for (uint32_t l = 0; l < n; ++l) {
    if (a.lanes == L1Lanes::Pixels)
      addr[l] = uint64_t{rect.pixel(first + l, image_width)} * a.stride + offset;
    else if (a.lanes == L1Lanes::Consecutive)
      addr[l] = (warp * kLanes + l) * a.stride + offset;
    else
      addr[l] = 0;
  }
  return n;
}

}  // namespace

double l1_request_wavefronts(const GpuModelConfig& gpu, const uint64_t* addr, uint32_t n, uint32_t width) {
  if (n == 0) return 0.0;
  if (gpu.gpu.l1_words) return hopper_l1_cycles(addr, n, width);
  uint64_t sectors[kLanes * 2], lines[kLanes * 2], words[kLanes * 4];
  uint32_t s = 0, l = 0, wc = 0;
  const uint64_t sector = gpu.cache.sector_bytes, line = gpu.cache.line_bytes;
  for (uint32_t i = 0; i < n && i < kLanes; ++i) {
    const uint64_t last = addr[i] + width - 1;
    for (uint64_t x = addr[i] / sector; x <= last / sector && s < std::size(sectors); ++x) sectors[s++] = x;
    for (uint64_t x = addr[i] / line; x <= last / line && l < std::size(lines); ++x) lines[l++] = x;
    for (uint64_t x = addr[i] / 4; x <= last / 4 && wc < std::size(words); ++x) words[wc++] = x;
  }
  if (gpu.gpu.l1_banks) return l1_bank_cycles(sectors, distinct(sectors, s), gpu.gpu.l1_banks);
  const double tags = std::ceil(distinct(lines, l) / gpu.gpu.l1_tags_per_clk);
  const double data = std::ceil(4.0 * distinct(words, wc) / 128.0);  // the L1's 128-byte data path
  return std::max({1.0, tags, data});
}

double l1_warp_wavefronts(const GpuModelConfig& gpu, const StageWork& w, const L1Inventory& inventory) {
  if (w.width <= 0 || w.height <= 0 || inventory.size == 0) return 0.0;
  const TileGrid grid(w.width, w.height, w.tile_w, w.tile_h);
  double wavefronts = 0;
  uint64_t warps = 0;
  uint64_t addr[kLanes];
  for (int t = 0; t < std::min(grid.count(), static_cast<int>(kSampleTiles)); ++t) {
    const TileRect rect = grid.rect(t);
    for (uint32_t first = 0; first < rect.area(); first += kLanes, ++warps) {
      for (size_t r = 0; r < inventory.size; ++r) {
        const L1Access& a = inventory.rows[r];
        for (uint32_t i = 0; i < a.count; ++i) {
          const uint32_t n = lane_addresses(a, i, rect, w.width, first, warps, addr);
          wavefronts += l1_request_wavefronts(gpu, addr, n, a.width);
        }
      }
    }
  }
  return warps ? wavefronts / double(warps) : 0.0;
}

double stage_l1_ms(const GpuModelConfig& gpu, double warps, double wavefronts) {
  const double cycles = warps * wavefronts / (double(gpu.cache.sms) * kL1WavefrontsPerCycle);
  return cycles / (gpu.gpu.clock_mhz * 1e3);
}

// The inventories. Counts: scripts/count-stage-instructions sm_90 --loads (nvcc 13; every instruction once, as the
// instruction term counts them), results/model/wide-gbuffer-loads/loads-sm_90.txt (Wide64) and
// loads-before-sm_90.txt (Fields60). Offsets in the 64-byte ShadingPoint (core/shading_point.h) and the 60-byte
// record before it: position 0, ng 12, ns 24, wo 36, prim 48, material 52, cls 56, front_face 57.
namespace {

// tile_hits_kernel (cuda/device_generators.cu): has_hit(points[...]) reads prim, one 4-byte load; thread 0 writes
// the tile's count (priced once per warp).
constexpr L1Access kTileHits64[] = {{1, 4, L1Lanes::Pixels, 64, 48}, {1, 4, L1Lanes::Uniform, 0, 0}};
constexpr L1Access kTileHits60[] = {{1, 4, L1Lanes::Pixels, 60, 48}, {1, 4, L1Lanes::Uniform, 0, 0}};

// noopt_kernel (cuda/device_per_pixel.cu, per_pixel_rays). Besides the point, both revisions load materials[
// sp.material] (BsdfParams) and offsets[t]: 14 LDG.E and 2 LDG.E.U8, taken as one address per warp (a warp's
// pixels mostly share a material; more materials in a warp cost more). write_ray (core/batch_view.h) stores to
// consecutive slots: weight and normal (Vec3 columns: 6 STG.E at a 12-byte stride), pixel and pdf (2 STG.E), the
// ray's two 16-byte words (2 STG.E.128 at a 32-byte stride), the material class (1 STG.E.U8).
// Since 63b5750 the point is load_point (device_per_pixel.cu line 37): four LDG.E.128.CONSTANT.
constexpr L1Access kNoopt64[] = {{4, 16, L1Lanes::Pixels, 64, 0},  // load_point
                                 {14, 4, L1Lanes::Uniform, 0, 0},      {2, 1, L1Lanes::Uniform, 0, 0},
                                 {6, 4, L1Lanes::Consecutive, 12, 0},  {2, 4, L1Lanes::Consecutive, 4, 0},
                                 {2, 16, L1Lanes::Consecutive, 32, 0}, {1, 1, L1Lanes::Consecutive, 1, 0}};
// Before: 14 LDG.E (the record's words 0-13) and 2 LDG.E.U8 (cls, front_face).
constexpr L1Access kNoopt60[] = {
    {14, 4, L1Lanes::Pixels, 60, 0},    {2, 1, L1Lanes::Pixels, 60, 56},  // the point, field by field
    {14, 4, L1Lanes::Uniform, 0, 0},    {2, 1, L1Lanes::Uniform, 0, 0},       {6, 4, L1Lanes::Consecutive, 12, 0},
    {2, 4, L1Lanes::Consecutive, 4, 0}, {2, 16, L1Lanes::Consecutive, 32, 0}, {1, 1, L1Lanes::Consecutive, 1, 0}};

// group_kernel (cuda/device_grouping.cu, the phases of generators/grouping_block.h). Besides the points: 37 LDG.E
// and 6 LDG.E.U8 (materials, offsets, scanline slots), one address per warp as noopt's; write_group_ray: noopt's
// stores and the tile and group columns (10 STG.E, 2 STG.E.128, 2 STG.E.U8 with group_type).
// Since 63b5750 every phase reads through load_point: 8 LDG.E.128.CONSTANT, and the words a phase narrows
// (group_ref reads ns only): 3 LDG.E.64.CONSTANT, 16 LDG.E.CONSTANT. All are priced with the pixel phases' lanes
// (a group phase's lanes read their donors' points: fewer lanes, scattered in the tile).
constexpr L1Access kGroup64[] = {
    {8, 16, L1Lanes::Pixels, 64, 0},    {3, 8, L1Lanes::Pixels, 64, 24},      {16, 4, L1Lanes::Pixels, 64, 0},
    {37, 4, L1Lanes::Uniform, 0, 0},    {6, 1, L1Lanes::Uniform, 0, 0},       {6, 4, L1Lanes::Consecutive, 12, 0},
    {4, 4, L1Lanes::Consecutive, 4, 0}, {2, 16, L1Lanes::Consecutive, 32, 0}, {2, 1, L1Lanes::Consecutive, 1, 0}};
// Before: 92 LDG.E and 12 LDG.E.U8, of which the 37 and 6 above are not the point's (63b5750 changed only the
// point reads): 55 4-byte field loads and 6 of cls / front_face.
constexpr L1Access kGroup60[] = {
    {55, 4, L1Lanes::Pixels, 60, 0},    {6, 1, L1Lanes::Pixels, 60, 56},  // the points, field by field
    {37, 4, L1Lanes::Uniform, 0, 0},    {6, 1, L1Lanes::Uniform, 0, 0},       {6, 4, L1Lanes::Consecutive, 12, 0},
    {4, 4, L1Lanes::Consecutive, 4, 0}, {2, 16, L1Lanes::Consecutive, 32, 0}, {2, 1, L1Lanes::Consecutive, 1, 0}};

template <size_t N>
L1Inventory inventory(const L1Access (&rows)[N]) {
  return L1Inventory{rows, N};
}

}  // namespace

L1Inventory tile_hits_l1(GBufferRead read) {
  return read == GBufferRead::Fields60 ? inventory(kTileHits60) : inventory(kTileHits64);
}
L1Inventory noopt_l1(GBufferRead read) {
  return read == GBufferRead::Fields60 ? inventory(kNoopt60) : inventory(kNoopt64);
}
L1Inventory group_l1(GBufferRead read) {
  return read == GBufferRead::Fields60 ? inventory(kGroup60) : inventory(kGroup64);
}

}  // namespace raycoh
