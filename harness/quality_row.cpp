#include "harness/quality_row.h"

namespace raycoh {

const Schema<QualityRow>& quality_schema() {
  using namespace csv_format;
  using R = QualityRow;
  using G = GeneralOrEmpty;
  static const Schema<R> schema = [] {
    Schema<R> s = {
        column("scene", &R::scene, Text{}),
        column("scene_spec", &R::scene_spec, Text{}, Key::Yes),
        column("scene_triangles", &R::scene_triangles, Integer<size_t>{}),
        column("scene_fingerprint", &R::scene_fingerprint, Text{}),
        column("method", &R::method, Text{}, Key::Yes),
        column("generator", &R::generator, Text{}),
        column("generator_params", &R::generator_params, Text{}),
        column("tracer_spec", &R::tracer_spec, Text{}, Key::Yes),
        column("tracer", &R::tracer, Text{}),
        column("tracer_params", &R::tracer_params, Text{}),
        column("width", &R::width, Integer<int>{}, Key::Yes),
        column("height", &R::height, Integer<int>{}, Key::Yes),
        column("frames", &R::frames, Integer<int>{}, Key::Yes),
        column("ref_frames", &R::ref_frames, Integer<int>{}, Key::Yes),
        column("bias_renders", &R::bias_renders, Integer<int>{}, Key::Yes),
        column("seed", &R::seed, Integer<uint32_t>{}, Key::Yes),
        column("ref_seed", &R::ref_seed, Optional<Integer<uint32_t>>{}),
        column("max_depth", &R::max_depth, Integer<int>{}, Key::Yes),
        column("rr_depth", &R::rr_depth, Integer<int>{}, Key::Yes),
        column("tone_map", &R::tone_map, Text{}, Key::Yes),
        column("exposure", &R::exposure, G{}),
        column("reference_kind", &R::reference_kind, Text{}, Key::Yes),
        column("reference", &R::reference, Text{}),
        column("psnr", &R::psnr, G{}),
        column("psnr_std", &R::psnr_std, G{}),
        column("ssim", &R::ssim, G{}),
        column("rmse", &R::rmse, G{}),
        column("rel_mse", &R::rel_mse, G{}),
        column("mse", &R::mse, G{}),
        column("mse_of_mean", &R::mse_of_mean, G{}),
        column("bias2", &R::bias2, G{}),
        column("variance", &R::variance, G{}),
        column("non_finite_samples", &R::non_finite_samples, Integer<uint64_t>{}),
        column("non_finite_pixels", &R::non_finite_pixels, Integer<uint64_t>{}),
        column("ref_non_finite_samples", &R::ref_non_finite_samples, Integer<uint64_t>{}),
        column("render_s", &R::render_s, G{}),
        column("trace_s", &R::trace_s, G{}),
        column("gen_ms", &R::gen_ms, G{}),
        column("rays", &R::rays, Integer<uint64_t>{}),
        column("mray_s", &R::mray_s, G{}),
        column("below_geometric", &R::below_geometric, Integer<size_t>{}),
        column("reused_rays", &R::reused_rays, Integer<size_t>{}),
    };
    append_columns(s, provenance_schema(), &R::provenance);
    return s;
  }();
  return schema;
}

}  // namespace raycoh
