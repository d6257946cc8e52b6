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
// (mean per ray).
#include <algorithm>
#include <cstdio>
#include <string>

#include "bvh/bvh_build.h"
#include "core/error.h"
#include "encoders/keys.h"
#include "encoders/mlhcc_cuts.h"
#include "generators/generator.h"
#include "generators/pixel_order.h"
#include "pipeline/first_hits.h"
#include "plugins/tracer_registry.h"
#include "scenes/scene.h"
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

int run(int argc, char** argv) {
  if (argc < 3) throw Error("usage: raycoh_mlhcc_walks SCENE WxH [SEED [FRAME [GENERATOR [BITS [LAMBDA [L]]]]]]");
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
