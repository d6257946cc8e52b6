// raycoh_mlhcc_walks: the trip counts of MLHCC's key kernel on one secondary pass (the stage model's trip-counted
// key term, simt/stage_paths.h; results/model/stage-trip-counts/). The pass is made on the CPU as `raycoh rays`
// makes it (the scene, its BVH, the first hits in 8x8 tile order, the generator's batch: the batch the device
// pipeline makes from the same G-buffer), and for every warp of 32 consecutive rays, as the key kernel runs them
// (a thread per ray, cuda/device_keys.cu), the iterations of the two cut walks (encoders/keys.h mlhcc_write_path:
// the origin's, then the estimated end point's), the largest over the warp's lanes (a warp runs a loop until its
// last lane leaves it). No time is read or made: workload counts for the model. Usage:
//   raycoh_mlhcc_walks SCENE WIDTHxHEIGHT [SEED [FRAME [GENERATOR [KEY_BITS [LAMBDA [L]]]]]]
// defaults: seed 1, frame 0, noopt, 32 bits, lambda 0.125, L 0.25 (the encoder's defaults). Prints one CSV line:
// scene,rays,warps,origin_trips,end_trips (mean per warp of the warp's largest), ray_origin_trips, ray_end_trips
// (mean per ray). --l1 FILE also writes to FILE (a header and one line) the MODELED L1 of the key kernel's global
// loads on the h200 preset, per warp (bench/mlhcc_key_l1.h; results/model/stage-counters/mlhcc-key-l1.md);
// --resident N replaces the resident blocks per SM the occupancy gives (6) in that replay.
#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "bench/mlhcc_key_l1.h"
#include "bvh/bvh_build.h"
#include "core/error.h"
#include "encoders/keys.h"
#include "encoders/mlhcc_cuts.h"
#include "generators/generator.h"
#include "generators/pixel_order.h"
#include "pipeline/first_hits.h"
#include "plugins/tracer_registry.h"
#include "scenes/scene.h"
#include "simt/gpu_model.h"
#include "tracers/tracer.h"

namespace raycoh {
namespace {

// The iterations mlhcc_write_path's loop starts for one point: the walk itself, counted as it runs (its code is
// dropped).
int walk_trips(const MlhccCuts& cuts, Vec3 p, int field_stride, int field_index, int needed_bits) {
  uint64_t code = 0;
  int trips = 0;
  mlhcc_write_path(cuts, p, field_stride, field_index, needed_bits, code, [&trips](int32_t) { ++trips; });
  return trips;
}

// Removes "--l1 FILE" and "--resident N" from argv (argc shrinks), wherever they stand.
void take_options(int& argc, char** argv, std::string& l1_path, uint32_t& resident) {
  int out = 1;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if ((a == "--l1" || a == "--resident") && i + 1 >= argc) throw Error(a + " needs a value");
    if (a == "--l1")
      l1_path = argv[++i];
    else if (a == "--resident")
      resident = static_cast<uint32_t>(std::stoul(argv[++i]));
    else
      argv[out++] = argv[i];
  }
  argc = out;
}

constexpr uint32_t kBlockThreads = 256;  // cuda/device_keys.cu kBlock
constexpr uint32_t kKeyRegisters = 38;   // key_kernel<mlhcc,u32> on sm_90 (stage-latency/registers-sm_90.txt)

// Blocks of the key kernel resident on one SM: registers per warp rounded up to the allocation unit, then the
// SM's warp and block limits (the CUDA occupancy rules; the kernel has no shared memory). h200: 1280 registers
// a warp, 51 warps, 6 blocks of 8.
uint32_t key_resident_blocks(const GpuSpec& g) {
  const uint32_t per_warp = (kKeyRegisters * 32 + g.reg_alloc_unit - 1) / g.reg_alloc_unit * g.reg_alloc_unit;
  const uint32_t warps = std::min(g.max_warps_per_sm, g.regs_per_sm / per_warp);
  return std::max(1u, std::min(g.max_blocks_per_sm, warps / (kBlockThreads / 32)));
}

// The lanes of one block (rays block x 256 ...) as the key kernel runs them: each ray's two walks.
void fill_block(const RayBatch& batch, const MlhccCuts& cuts, const Bounds& box, int bits, float length, uint64_t block,
                keyl1::Warp* warps) {
  for (uint32_t t = 0; t < kBlockThreads; ++t) {
    keyl1::Lane& lane = warps[t / 32][t % 32];
    lane.ray = block * kBlockThreads + t;
    lane.active = lane.ray < batch.size();
    for (auto& w : lane.walk) w.clear();
    if (!lane.active) continue;
    const Ray& r = batch.rays[lane.ray];
    keyl1::record_walk(cuts, clamp_to_box(r.org, box), 2, 0, bits, lane.walk[0]);
    const Vec3 end = clamp_to_box(estimated_end_point(r.org, r.dir, r.tmax, box, length), box);
    keyl1::record_walk(cuts, end, 2, 1, bits, lane.walk[1]);
    if (!keyl1::walk_is_consistent(cuts, lane.walk[0]) || !keyl1::walk_is_consistent(cuts, lane.walk[1]))
      throw Error("ray " + std::to_string(lane.ray) + ": a recorded walk the loop cannot make");
  }
}

// The L1 file: a header and one line, every count per warp (MODELED).
void write_l1_csv(const std::string& path, const std::string& scene, size_t rays, const keyl1::Counts& c,
                  const CacheModelConfig& cache, uint32_t resident, double most_o, double most_e) {
  using keyl1::kCut;
  using keyl1::kNode;
  using keyl1::kRay;
  FILE* f = std::fopen(path.c_str(), "w");
  if (!f) throw Error("cannot write " + path);
  const double w = std::max<double>(1.0, double(c.warps));
  const double sectors = double(c.total(c.sectors)), misses = double(c.total(c.misses));
  const double pending = double(c.total(c.pending));
  auto pct = [](double part, double all) { return all > 0 ? 100.0 * part / all : 0.0; };
  std::fprintf(f,
               "scene,rays,warps,sms,resident_blocks,l1_kib,l1_ways,origin_trips,end_trips,requests,sectors,"
               "l1_misses,l1_hit_pct,pending_hits,l1_hit_pct_pending_miss,l2_sectors,l2_bytes,dram_sectors,"
               "ray_requests,ray_sectors,ray_misses,node_requests,node_sectors,node_misses,cut_requests,cut_sectors,"
               "cut_misses,node_miss_steps,cut_miss_steps\n");
  std::fprintf(f, "%s,%zu,%.0f,%u,%u,%.0f,%u,%.3f,%.3f,%.3f,%.3f,%.3f,%.2f,%.3f,%.2f,%.3f,%.1f,%.3f", scene.c_str(),
               rays, w, cache.sms, resident, double(cache.l1.bytes) / 1024, cache.l1.ways, most_o / w, most_e / w,
               double(c.total(c.requests)) / w, sectors / w, misses / w, 100.0 - pct(misses, sectors), pending / w,
               100.0 - pct(misses + pending, sectors), misses / w, misses * cache.sector_bytes / w,
               double(c.l2_misses) / w);
  for (int s : {kRay, kNode, kCut})
    std::fprintf(f, ",%.3f,%.3f,%.3f", double(c.requests[s]) / w, double(c.sectors[s]) / w, double(c.misses[s]) / w);
  std::fprintf(f, ",%.3f,%.3f\n", double(c.miss_steps[kNode]) / w, double(c.miss_steps[kCut]) / w);
  std::fclose(f);
}

// MODELED: the key kernel's global loads replayed on the h200 preset's caches (bench/mlhcc_key_l1.h). Block b runs
// on SM b mod SMs; each SM runs its blocks in groups of `resident`, the groups of every SM in turn.
void write_l1(const std::string& path, const std::string& scene, const RayBatch& batch, const MlhccCuts& cuts,
              const Bounds& box, int bits, float length, uint32_t resident) {
  const GpuModelConfig gpu = gpu_preset("h200");
  if (resident == 0) resident = key_resident_blocks(gpu.gpu);
  const uint32_t sms = gpu.cache.sms, warps_per_block = kBlockThreads / 32;
  keyl1::Replay replay(gpu.cache, keyl1::packed_layout(batch.size(), cuts.node_count));
  const uint64_t blocks = (batch.size() + kBlockThreads - 1) / kBlockThreads;
  std::vector<keyl1::Warp> group(size_t(resident) * warps_per_block);
  double most_o = 0, most_e = 0;
  for (uint64_t first = 0; first < blocks; first += uint64_t(resident) * sms)
    for (uint32_t sm = 0; sm < sms; ++sm) {
      size_t count = 0;
      for (uint64_t b = first + sm; b < blocks && b < first + uint64_t(resident) * sms; b += sms) {
        fill_block(batch, cuts, box, bits, length, b, &group[count]);
        count += warps_per_block;
      }
      for (size_t i = 0; i < count; ++i) {
        size_t o = 0, e = 0;
        for (const keyl1::Lane& l : group[i]) o = std::max(o, l.walk[0].size()), e = std::max(e, l.walk[1].size());
        most_o += o;
        most_e += e;
      }
      if (count > 0) replay.replay_group(sm, group.data(), count);
    }
  write_l1_csv(path, scene, batch.size(), replay.counts(), gpu.cache, resident, most_o, most_e);
}

int run(int argc, char** argv) {
  std::string l1_path;
  uint32_t resident = 0;
  take_options(argc, argv, l1_path, resident);
  if (argc < 3)
    throw Error(
        "usage: raycoh_mlhcc_walks SCENE WxH [SEED [FRAME [GENERATOR [BITS [LAMBDA [L]]]]]] [--l1 FILE [--resident "
        "N]]");
  int width = 0, height = 0;
  if (std::sscanf(argv[2], "%dx%d", &width, &height) != 2) throw Error("resolution WxH expected");
  const uint32_t seed = argc > 3 ? static_cast<uint32_t>(std::stoul(argv[3])) : 1u;
  const uint32_t frame = argc > 4 ? static_cast<uint32_t>(std::stoul(argv[4])) : 0u;
  const std::string gen = argc > 5 ? argv[5] : "noopt";
  const int bits = argc > 6 ? std::stoi(argv[6]) : 32;
  const float lambda = argc > 7 ? std::stof(argv[7]) : 0.125f, length = argc > 8 ? std::stof(argv[8]) : 0.25f;
  const Scene scene = load_scene(argv[1]);
  const Bvh bvh = build_bvh(scene);
  auto tracer = make_tracer({"cpu", ""}, scene, bvh);
  const auto order = make_pixel_order(width, height, RayOrder::Tile, 8, 8);
  const GBuffer gbuffer = first_hits(scene, *tracer, width, height, order, seed, frame, true).gbuffer;
  auto generator = make_generator(parse_plugin_spec(gen));
  RayBatch batch;
  GenerationStats stats;
  generator->generate(scene, gbuffer, seed, batch, stats);
  const MlhccCutTable table = build_mlhcc_cuts(bvh, lambda, MlhccRanks::Compressed);
  const MlhccCuts cuts = table.view();
  const Bounds box = scene.bounds;
  double warp_o = 0, warp_e = 0, ray_o = 0, ray_e = 0, warps = 0;
  for (size_t w = 0; w < batch.size(); w += 32) {
    int most_o = 0, most_e = 0;
    for (size_t i = w; i < std::min(batch.size(), w + 32); ++i) {
      const Ray& r = batch.rays[i];
      const int o = walk_trips(cuts, clamp_to_box(r.org, box), 2, 0, bits);
      const int e =
          walk_trips(cuts, clamp_to_box(estimated_end_point(r.org, r.dir, r.tmax, box, length), box), 2, 1, bits);
      most_o = std::max(most_o, o);
      most_e = std::max(most_e, e);
      ray_o += o;
      ray_e += e;
    }
    warp_o += most_o;
    warp_e += most_e;
    ++warps;
  }
  const double n = std::max<double>(1.0, double(batch.size()));
  warps = std::max(1.0, warps);
  std::printf(
      "scene,rays,warps,origin_trips,end_trips,ray_origin_trips,ray_end_trips\n%s,%zu,%.0f,%.3f,%.3f,%.3f,%.3f\n",
      scene.name.c_str(), batch.size(), warps, warp_o / warps, warp_e / warps, ray_o / n, ray_e / n);
  if (!l1_path.empty()) write_l1(l1_path, scene.name, batch, cuts, box, bits, length, resident);
  return 0;
}

}  // namespace
}  // namespace raycoh

int main(int argc, char** argv) {
  try {
    return raycoh::run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "raycoh_mlhcc_walks: %s\n", e.what());
    return 2;
  }
}
