// Streaming-kernel models of the pipeline stages around the trace; see pipeline_model.h.
#include "simt/pipeline_model.h"

#include <algorithm>

#include "core/ray_batch.h"
#include "simt/stage_model.h"

namespace raycoh {
namespace {

constexpr size_t kIndexBytes = 4;
constexpr uint32_t kWarp = 32;
constexpr uint32_t kSectorBytes = 32;

// The batch columns a trace and shading need (RAYCOH_BATCH_COLUMNS without the group columns), element sizes in
// bytes.
constexpr size_t kArrays[] = {
#define RAYCOH_COLUMN_SIZE(name, T, grouped) grouped ? size_t{0} : sizeof(T),
    RAYCOH_BATCH_COLUMNS(RAYCOH_COLUMN_SIZE)
#undef RAYCOH_COLUMN_SIZE
};

}  // namespace

size_t batch_bytes_per_ray() {
  size_t b = 0;
  for (size_t a : kArrays) b += a;
  return b;
}

double window_bytes(size_t n, bool physical) {
  if (n < 2) return 0.0;
  return physical ? 2.0 * double(n) * batch_bytes_per_ray() : double(n) * (sizeof(Ray) + kIndexBytes);
}

// The generators read every pixel's whole point (64 bytes: core/shading_point.h; the device in four 16-byte
// loads) and write the batch.
double generation_bytes(size_t pixels, size_t rays) {
  return double(pixels) * sizeof(ShadingPoint) + double(rays) * batch_bytes_per_ray();
}

double modeled_generation_ms(const GpuModelConfig& gpu, size_t pixels, size_t rays) {
  StageWork w;  // pixels / 64 tiles of 64 pixels: a row of 64 x 1 tiles has 8x8's tiles and warps
  w.width = static_cast<int>(pixels);
  w.height = 1;
  w.tile_w = 64;
  w.tile_h = 1;
  w.rays = rays;
  return stage_generation_ms(gpu, w);
}

double key_bytes(size_t rays, int key_bits) {
  if (key_bits == 0) return 0.0;
  return double(rays) * (sizeof(Ray) + key_bits / 8 + kIndexBytes);
}

double sort_bytes(size_t n, int key_bits) {
  if (key_bits == 0 || n < 2) return 0.0;
  const double key = key_bits / 8.0;
  const int passes = (key_bits + 7) / 8;
  return double(n) * (key + passes * 2.0 * (key + kIndexBytes));
}

double permute_bytes(const uint32_t* order, size_t n) {
  if (n == 0) return 0.0;
  double read_sectors = 0;
  uint64_t first[kWarp * 2], last[kWarp * 2];
  for (size_t a : kArrays) {
    if (a == 0) continue;  // a group column: not part of the traced batch
    for (size_t w = 0; w < n; w += kWarp) {
      const size_t lanes = std::min<size_t>(kWarp, n - w);
      size_t m = 0;
      for (size_t l = 0; l < lanes; ++l) {
        const uint64_t byte = uint64_t{order[w + l]} * a;
        first[m] = byte / kSectorBytes;
        last[m++] = (byte + a - 1) / kSectorBytes;
      }
      // Distinct sectors of the warp's gathers: sort the first sectors, add the straddling second ones.
      uint64_t all[kWarp * 2];
      size_t k = 0;
      for (size_t i = 0; i < m; ++i) {
        all[k++] = first[i];
        if (last[i] != first[i]) all[k++] = last[i];
      }
      std::sort(all, all + k);
      read_sectors += double(std::unique(all, all + k) - all);
    }
  }
  return read_sectors * kSectorBytes + double(n) * batch_bytes_per_ray();
}

ModeledStages stage_traffic(size_t pixels, int key_bits, int window, bool physical, size_t rays,
                            const std::vector<uint32_t>& order, bool fused) {
  ModeledStages m;
  m.gen_bytes = fused ? double(pixels) * sizeof(ShadingPoint) : generation_bytes(pixels, rays);
  if (key_bits == 0 || fused) return m;
  if (window > 0) {
    m.sort_bytes = window_bytes(rays, physical);
    return m;
  }
  m.key_bytes = key_bytes(rays, key_bits);
  m.sort_bytes = sort_bytes(rays, key_bits);
  if (physical) m.permute_bytes = permute_bytes(order.data(), order.size());
  return m;
}

}  // namespace raycoh
