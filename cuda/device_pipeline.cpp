#include "cuda/device_pipeline.h"

#include <fmt/format.h>

#include <cstring>
#include <memory>
#include <utility>

#include "bvh/bvh_build.h"
#include "core/error.h"
#include "cuda/device_gbuffer.h"
#include "cuda/device_generators.h"
#include "cuda/device_keys.h"
#include "cuda/device_stages.h"
#include "encoders/encoder.h"
#include "generators/generator.h"
#include "scenes/scene.h"

namespace raycoh::cuda {

namespace {

// Two recipes make the same keys (the BVH is the pipeline's own, so mlhcc's cuts follow from the recipe).
bool same_recipe(const KeyRecipe& a, const KeyRecipe& b) {
  return a.kind == b.kind && a.bits == b.bits && std::memcmp(&a.box, &b.box, sizeof(Bounds)) == 0 &&
         a.length_factor == b.length_factor && a.lambda == b.lambda && a.with_end == b.with_end &&
         a.global_ranks == b.global_ranks;
}

class CudaPipeline final : public DevicePipeline {
 public:
  CudaPipeline(const Scene& scene, const Bvh& bvh, PipelineTrace trace)
      : scene_(scene),
        bvh_(bvh),
        trace_(std::move(trace)),
        generator_(scene),
        mesh_(scene),
        gbuffer_(scene, mesh_.view()) {
    RAYCOH_CHECK(trace_.tracer != nullptr, "the device pipeline needs the cuda tracer's DeviceTracer");
    RAYCOH_CHECK(!trace_.counting || trace_.counted, "a counting device pipeline needs somewhere to put the counts");
  }

  std::string refusal(const std::string& generator_name, const Generator& generator,
                      const Encoder& encoder) const override {
    return device_pipeline_refusal(generator_name, generator, encoder, trace_.fused);
  }

  DeviceStageTimes primary(int width, int height, int tile_w, int tile_h, uint32_t seed, uint32_t frame,
                           bool jitter) override {
    last_ = Pass::None;
    stages_.start_span();
    stages_.launch_primary(scene_.camera, width, height, tile_w, tile_h, seed, frame, jitter);
    const size_t n = stages_.primary_count();
    const float trace_ms = trace(stages_.primary_rays(), nullptr, n, stages_.hits(n));
    stages_.stop_span();
    DeviceStageTimes t;
    t.gen_ms = stages_.wait_primary_ms();
    t.trace_ms = trace_ms >= 0.f ? trace_ms : trace_.tracer->wait_kernel_ms();
    t.span_ms = stages_.wait_span_ms();
    last_ = Pass::Primary;
    last_n_ = n;
    width_ = width;
    height_ = height;
    frame_ = frame;
    return t;
  }

  void first_hits_gbuffer() override {
    if (last_ != Pass::Primary) throw Error("cuda: first_hits_gbuffer: the last pass was not a primary pass");
    gbuffer_.launch(stages_.primary_rays(), stages_.primary_pixels(), stages_.hits(last_n_), last_n_, width_, height_,
                    frame_);
    generator_.use_device(gbuffer_.finish());
    gbuffer_ready_ = true;
  }

  GBuffer download_gbuffer() const override {
    if (!gbuffer_ready_) throw Error("cuda: download_gbuffer before first_hits_gbuffer");
    return gbuffer_.download();
  }

  DeviceStageTimes secondary(const Generator& generator, const Encoder& encoder, PermuteMode mode, uint32_t seed,
                             GenerationStats& stats) override {
    if (!gbuffer_ready_) throw Error("cuda: a secondary pass before first_hits_gbuffer (no G-buffer on the device)");
    last_ = Pass::None;
    if (trace_.fused) return secondary_fused(generator, encoder, seed, stats);
    DeviceKeys* keys = keys_for(encoder);
    const bool physical = keys && mode == PermuteMode::Physical;
    stages_.start_span();
    generator_.launch(seed, generator);
    const size_t n = generator_.device_count();
    const BatchView batch = generator_.device_batch();
    const Ray* rays = batch.rays;
    const uint32_t* order = nullptr;
    if (keys) {
      keys->sort_device(batch.rays, n);
      if (physical)
        rays = stages_.launch_gather(batch, keys->device_order(), n).rays;
      else
        order = keys->device_order();
    }
    const float trace_ms = trace(rays, order, n, stages_.hits(n));
    stages_.stop_span();
    DeviceStageTimes t;
    generator_.finish(stats);
    t.gen_ms = generator_.last_kernel_ms();
    if (keys) {
      const GpuReorderTimings k = keys->wait_timings();
      t.key_ms = k.key_ms;
      t.sort_ms = k.sort_ms;
    }
    if (physical) t.permute_ms = stages_.wait_permute_ms();
    t.trace_ms = trace_ms >= 0.f ? trace_ms : trace_.tracer->wait_kernel_ms();
    t.span_ms = stages_.wait_span_ms();
    last_ = Pass::Secondary;
    last_n_ = n;
    last_keys_ = keys;
    last_physical_ = physical;
    last_fused_ = false;
    return t;
  }

  void download_primary(PixelRays& rays, std::vector<Hit>& hits) const override {
    if (last_ != Pass::Primary) throw Error("cuda: download_primary: the last pass was not a primary pass");
    stages_.download_primary(rays);
    stages_.download_hits(hits, last_n_);
  }

  void download_secondary(RayBatch& generated, std::vector<uint32_t>& order, RayBatch& permuted,
                          std::vector<Hit>& hits) const override {
    if (last_ != Pass::Secondary) throw Error("cuda: download_secondary: the last pass was not a secondary pass");
    order.clear();
    permuted = RayBatch{};
    if (last_fused_) {
      download_fused(generated, hits);
      return;
    }
    generator_.download(generated);
    if (last_keys_) {
      order.resize(last_n_);
      last_keys_->download_order(order.data(), last_n_);
    }
    if (last_physical_) {
      stages_.download_permuted(permuted, last_n_);
      permuted.width = generated.width;
      permuted.height = generated.height;
      permuted.frame = generated.frame;
    }
    stages_.download_hits(hits, last_n_);
  }

 private:
  enum class Pass { None, Primary, Secondary };

  // pipeline=fused: one kernel makes and traces each tile's rays (hits at their pixels); its time is trace_ms.
  DeviceStageTimes secondary_fused(const Generator& generator, const Encoder& encoder, uint32_t seed,
                                   GenerationStats& stats) {
    if (encoder.key_bits() > 0)
      throw Error(fmt::format("cuda: encoder '{}' sorts a batch; cuda:pipeline=fused keeps none", encoder.name()));
    const size_t pixels = gbuffer_.view().pixels();
    stages_.start_span();
    generator_.launch_fused(seed, generator, *trace_.tracer, trace_.launch, stages_.hits(pixels));
    stages_.stop_span();
    generator_.finish(stats);
    DeviceStageTimes t;
    t.fused = true;
    t.trace_ms = generator_.last_kernel_ms();
    t.span_ms = stages_.wait_span_ms();
    last_ = Pass::Secondary;
    last_n_ = generator_.device_count();
    last_keys_ = nullptr;
    last_physical_ = false;
    last_fused_ = true;
    last_generator_ = &generator;
    last_seed_ = seed;
    return t;
  }

  // The batch of the last fused pass, made again by the materialized device generator (equal to the CPU's), and the
  // fused hits in its order.
  void download_fused(RayBatch& generated, std::vector<Hit>& hits) const {
    GenerationStats unused;
    generator_.launch(last_seed_, *last_generator_);
    generator_.finish(unused);
    generator_.download(generated);
    std::vector<Hit> at_pixel;
    stages_.download_hits(at_pixel, gbuffer_.view().pixels());
    hits.resize(generated.size());
    for (size_t i = 0; i < generated.size(); ++i) hits[i] = at_pixel[generated.pixel[i]];
  }

  // Queues the trace stage; returns -1 for the timing kernel (its time is read after the span closes), or the
  // counting kernel's time (it waits for its counters, which go to trace_.counted).
  float trace(const Ray* rays, const uint32_t* order, size_t n, Hit* hits) {
    if (!trace_.counting) {
      trace_.tracer->launch_device(rays, order, n, hits, trace_.launch);
      return -1.f;
    }
    trace_.tracer->trace_counting_device(rays, order, n, hits, trace_.layout, trace_.launch.block, warps_);
    trace_.counted(warps_, n);
    return trace_.tracer->last_kernel_ms();
  }

  // The encoder's keys on the device, made when first asked for (nullptr for an encoder without keys).
  DeviceKeys* keys_for(const Encoder& encoder) {
    if (encoder.key_bits() == 0) return nullptr;
    const KeyRecipe recipe = encoder.recipe();
    if (recipe.kind == KeyKind::None || recipe.bits != encoder.key_bits())
      throw Error(fmt::format("encoder '{}' has no device version", encoder.name()));
    for (auto& [r, keys] : keys_)
      if (same_recipe(r, recipe)) return keys.get();
    keys_.emplace_back(recipe, std::make_unique<DeviceKeys>(recipe, &bvh_));
    return keys_.back().second.get();
  }

  const Scene& scene_;
  const Bvh& bvh_;
  PipelineTrace trace_;
  mutable DeviceGenerator generator_;  // mutable: a fused pass's batch is made again when downloaded
  DeviceStages stages_;
  DeviceMesh mesh_;
  DeviceGBuffer gbuffer_;  // the last primary pass's, made on the device (first_hits_gbuffer)
  std::vector<std::pair<KeyRecipe, std::unique_ptr<DeviceKeys>>> keys_;
  bool gbuffer_ready_ = false;
  int width_ = 0, height_ = 0;  // the last primary pass's
  uint32_t frame_ = 0;
  std::vector<WarpStepCounters> warps_;
  Pass last_ = Pass::None;
  size_t last_n_ = 0;
  DeviceKeys* last_keys_ = nullptr;
  bool last_physical_ = false;
  bool last_fused_ = false;
  const Generator* last_generator_ = nullptr;  // fused: the last pass's (download_secondary remakes its batch)
  uint32_t last_seed_ = 0;
};

}  // namespace

std::string device_pipeline_refusal(const std::string& generator_name, const Generator& generator,
                                    const Encoder& encoder, bool fused) {
  const char* const host = "; cuda:pipeline=host traces host-made batches of it";
  const DeviceRecipe device = generator.device_recipe();
  if (device.kind == DeviceRecipe::Kind::None)
    return fmt::format("generator '{}' has no device version; device generators: {}{}", generator_name,
                       kGpuGeneratorNames, host);
  try {
    check_gpu_generator(generator, fused);
  } catch (const Error& e) {
    return fmt::format("generator '{}': {}{}", generator_name, e.what(), host);
  }
  const KeyRecipe recipe = encoder.recipe();
  if (fused && encoder.key_bits() > 0)
    return fmt::format(
        "encoder '{}' sorts a batch, and cuda:pipeline=fused keeps none (it traces each ray where it "
        "is made): use encoder none, or cuda:pipeline=device",
        encoder.name());
  if (encoder.key_bits() > 0 && (recipe.kind == KeyKind::None || recipe.bits != encoder.key_bits()))
    return fmt::format("encoder '{}' has no device version; device encoders: none, {}{}", encoder.name(),
                       key_kind_names(), host);
  return "";
}

std::unique_ptr<DevicePipeline> make_device_pipeline(const Scene& scene, const Bvh& bvh, PipelineTrace trace) {
  return std::make_unique<CudaPipeline>(scene, bvh, std::move(trace));
}

}  // namespace raycoh::cuda
