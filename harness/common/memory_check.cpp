#include "harness/common/memory_check.h"

#include <fmt/format.h>

#include <cctype>
#include <cstdlib>
#include <fstream>
#include <string>

#include "core/error.h"
#include "core/ray.h"
#include "core/ray_batch.h"

namespace raycoh {

namespace {

constexpr uint64_t kNoLimit = ~uint64_t{0};

uint64_t parse_bytes(const std::string& text) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || end == text.c_str() || !(v >= 0))
    throw Error(fmt::format("RAYCOH_MEMORY_AVAILABLE={}: expected a number of bytes, optionally with K, M or G", text));
  const char unit = static_cast<char>(std::toupper(static_cast<unsigned char>(*end)));
  const double scale = unit == 'K' ? 1024.0 : unit == 'M' ? 1048576.0 : unit == 'G' ? 1073741824.0 : 1.0;
  return static_cast<uint64_t>(v * scale);
}

uint64_t meminfo_available() {
  std::ifstream in("/proc/meminfo");
  std::string key;
  uint64_t kib = 0;
  std::string unit;
  while (in >> key >> kib >> unit)
    if (key == "MemAvailable:") return kib * 1024;
  return kNoLimit;
}

// cgroup v2: memory.max ("max" or bytes) minus memory.current.
uint64_t cgroup_available() {
  std::ifstream max_in("/sys/fs/cgroup/memory.max"), cur_in("/sys/fs/cgroup/memory.current");
  std::string max_text;
  uint64_t current = 0;
  if (!(max_in >> max_text) || max_text == "max" || !(cur_in >> current)) return kNoLimit;
  const uint64_t max = std::strtoull(max_text.c_str(), nullptr, 10);
  return max > current ? max - current : 0;
}

// One secondary batch: every array of RayBatch per ray.
constexpr uint64_t kBatchPerRay = sizeof(Ray) + 2 * sizeof(uint32_t) + sizeof(float) + 2 * sizeof(Vec3) +
                                  sizeof(MaterialClass) + 2 * sizeof(uint32_t) + sizeof(GroupType);

double gib(uint64_t bytes) { return static_cast<double>(bytes) / 1073741824.0; }

}  // namespace

uint64_t available_memory_bytes() {
  if (const char* env = std::getenv("RAYCOH_MEMORY_AVAILABLE"); env && *env) return parse_bytes(env);
  return std::min(meminfo_available(), cgroup_available());
}

uint64_t experiment_bytes(int width, int height) {
  const uint64_t pixels = static_cast<uint64_t>(width) * static_cast<uint64_t>(height);
  // Primary rays, their hits and the G-buffer; the batch, its sorted copy, the hits of a trace; keys (with the
  // radix sort's scratch), the order and the pixel order.
  const uint64_t per_pixel = sizeof(Ray) + 2 * sizeof(Hit) + sizeof(ShadingPoint) + 2 * kBatchPerRay +
                             2 * sizeof(uint64_t) + 2 * sizeof(uint32_t) + sizeof(uint32_t);
  return pixels * per_pixel;
}

uint64_t rendering_bytes(int width, int height) {
  const uint64_t pixels = static_cast<uint64_t>(width) * static_cast<uint64_t>(height);
  // Three accumulators (3 doubles + 2 counters each: the render, the mean of the renders, the reference) and four
  // float images; per bounce the G-buffer, a batch and the hits of primary and secondary rays.
  const uint64_t accumulator = 3 * sizeof(double) + 2 * sizeof(uint32_t);
  const uint64_t per_pixel = 3 * accumulator + 4 * sizeof(Vec3) + sizeof(ShadingPoint) + kBatchPerRay +
                             2 * sizeof(Hit) + sizeof(Ray) + sizeof(uint32_t);
  return pixels * per_pixel;
}

void check_memory(const std::string& what, uint64_t need) {
  const uint64_t available = available_memory_bytes();
  if (need <= available) return;
  throw Error(fmt::format(
      "{}: needs about {:.1f} GiB of memory for its per-pixel buffers (scene and BVH not counted), {:.1f} GiB are "
      "available; choose a smaller --res",
      what, gib(need), gib(available)));
}

}  // namespace raycoh
