// Streaming-kernel models of the pipeline stages around the trace; see pipeline_model.h.
#include "simt/pipeline_model.h"

#include <algorithm>

#include "core/ray_batch.h"

namespace raycoh {
namespace {

constexpr size_t kIndexBytes = 4;
constexpr uint32_t kWarp = 32;
constexpr uint32_t kSectorBytes = 32;

// The batch arrays, element sizes in bytes (core/ray_batch.h).
constexpr size_t kArrays[] = {sizeof(Ray),  sizeof(uint32_t), sizeof(float),
                              sizeof(Vec3), sizeof(Vec3),     sizeof(MaterialClass)};

}  // namespace

size_t batch_bytes_per_ray() {
  size_t b = 0;
  for (size_t a : kArrays) b += a;
  return b;
}

double modeled_stream_ms(const GpuModelConfig& gpu, double bytes) { return bytes / (gpu.gpu.dram_gb_s * 1e6); }

double modeled_generation_ms(const GpuModelConfig& gpu, size_t pixels, size_t rays) {
  return modeled_stream_ms(gpu, double(pixels) * sizeof(ShadingPoint) + double(rays) * batch_bytes_per_ray());
}

double modeled_key_ms(const GpuModelConfig& gpu, size_t rays, int key_bits) {
  if (key_bits == 0) return 0.0;
  return modeled_stream_ms(gpu, double(rays) * (sizeof(Ray) + key_bits / 8 + kIndexBytes));
}

double modeled_sort_ms(const GpuModelConfig& gpu, size_t n, int key_bits) {
  if (key_bits == 0 || n < 2) return 0.0;
  const double key_bytes = key_bits / 8.0;
  const int passes = (key_bits + 7) / 8;
  return modeled_stream_ms(gpu, double(n) * (key_bytes + passes * 2.0 * (key_bytes + kIndexBytes)));
}

double modeled_window_ms(const GpuModelConfig& gpu, size_t n, bool physical) {
  if (n < 2) return 0.0;
  return physical ? modeled_stream_ms(gpu, 2.0 * double(n) * batch_bytes_per_ray())
                  : modeled_stream_ms(gpu, double(n) * (sizeof(Ray) + kIndexBytes));
}

double modeled_permute_ms(const GpuModelConfig& gpu, const uint32_t* order, size_t n) {
  if (n == 0) return 0.0;
  double read_sectors = 0;
  uint64_t first[kWarp * 2], last[kWarp * 2];
  for (size_t a : kArrays) {
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
  return modeled_stream_ms(gpu, read_sectors * kSectorBytes + double(n) * batch_bytes_per_ray());
}

ModeledStages modeled_stages(const GpuModelConfig& gpu, size_t pixels, int key_bits, int window, bool physical,
                             size_t rays, const std::vector<uint32_t>& order) {
  ModeledStages m;
  m.gen_ms = modeled_generation_ms(gpu, pixels, rays);
  if (key_bits == 0) return m;
  if (window > 0) {
    m.sort_ms = modeled_window_ms(gpu, rays, physical);
    return m;
  }
  m.key_ms = modeled_key_ms(gpu, rays, key_bits);
  m.sort_ms = modeled_sort_ms(gpu, rays, key_bits);
  if (physical) m.permute_ms = modeled_permute_ms(gpu, order.data(), order.size());
  return m;
}

}  // namespace raycoh
