#include "records/quality_row.h"

namespace raycoh {

namespace {

using namespace csv_format;
using R = QualityRow;
using G = GeneralOrEmpty;

// What ran: the scene, method, tracer and render settings (most of them the row's key).
Schema<R> quality_run_columns() {
  return {
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
      column("protocol", &R::protocol, Text{}, Key::Yes),
      column("metrics", &R::metrics, Text{}, Key::Yes),
  };
}

// What it measured: the image metrics against the reference, the bias tests, FLIP and the render's timings.
Schema<R> quality_measure_columns() {
  return {
      column("psnr", &R::psnr, G{}),
      column("psnr_std", &R::psnr_std, G{}),
      column("ssim", &R::ssim, G{}),
      column("rmse", &R::rmse, G{}),
      column("rel_mse", &R::rel_mse, G{}),
      column("mse", &R::mse, G{}),
      column("mse_of_mean", &R::mse_of_mean, G{}),
      column("bias2", &R::bias2, G{}),
      column("variance", &R::variance, G{}),
      column("ref_noise_mse", &R::ref_noise_mse, G{}),
      column("ref_noise_rel_mse", &R::ref_noise_rel_mse, G{}),
      column("ref_noise_share", &R::ref_noise_share, G{}),
      column("ref_noise_residual_share", &R::ref_noise_residual_share, G{}),
      column("mse_corr", &R::mse_corr, G{}),
      column("rel_mse_corr", &R::rel_mse_corr, G{}),
      column("psnr_corr", &R::psnr_corr, G{}),
      column("bias2_corr", &R::bias2_corr, G{}),
      column("rel_mse_ds2", &R::rel_mse_ds2, G{}),
      column("rel_mse_ds4", &R::rel_mse_ds4, G{}),
      column("rel_mse_ds8", &R::rel_mse_ds8, G{}),
      column("rel_var", &R::rel_var, G{}),
      column("rel_var_ds8", &R::rel_var_ds8, G{}),
      column("bias_excluded", &R::bias_excluded, G{}),
      column("bias_excluded_dark", &R::bias_excluded_dark, G{}),
      column("bias_excluded_bright", &R::bias_excluded_bright, G{}),
      column("bias_excluded_skew", &R::bias_excluded_skew, G{}),
      column("bias_excluded_ds4", &R::bias_excluded_ds4, G{}),
      column("bias_mean", &R::bias_mean, G{}),
      column("bias_mean_ci", &R::bias_mean_ci, G{}),
      column("bias_mean_rel", &R::bias_mean_rel, G{}),
      column("bias_z2", &R::bias_z2, G{}),
      column("bias_verdict", &R::bias_verdict, Text{}),
      column("hybrid_diffuse_share", &R::hybrid_diffuse_share, G{}),
      column("flip", &R::flip, G{}),
      column("flip_hdr", &R::flip_hdr, G{}),
      column("flip_hdr_exposure", &R::flip_hdr_exposure, Text{}),
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
}

// --denoise: the denoiser (a key) and the figures on the denoised renders, after every earlier column.
Schema<R> quality_denoised_columns() {
  return {
      column("denoise", &R::denoise, Text{}, Key::Yes),
      column("denoised_psnr", &R::denoised_psnr, G{}),
      column("denoised_psnr_std", &R::denoised_psnr_std, G{}),
      column("denoised_ssim", &R::denoised_ssim, G{}),
      column("denoised_rmse", &R::denoised_rmse, G{}),
      column("denoised_rel_mse", &R::denoised_rel_mse, G{}),
      column("denoised_mse", &R::denoised_mse, G{}),
      column("denoised_rel_mse_ds8", &R::denoised_rel_mse_ds8, G{}),
      column("denoised_mse_corr", &R::denoised_mse_corr, G{}),
      column("denoised_rel_mse_corr", &R::denoised_rel_mse_corr, G{}),
      column("denoised_psnr_corr", &R::denoised_psnr_corr, G{}),
      column("denoise_s", &R::denoise_s, G{}),
  };
}

}  // namespace

const Schema<QualityRow>& quality_schema() {
  static const Schema<R> schema = [] {
    Schema<R> s = quality_run_columns();
    const Schema<R> measures = quality_measure_columns();
    s.insert(s.end(), measures.begin(), measures.end());
    append_columns(s, provenance_schema(), &R::provenance);
    append_columns(s, recorded_schema(), &R::recorded);
    s.push_back(column("rel_mse_renders", &R::rel_mse_renders, csv_format::Numbers{}));
    s.push_back(column("rel_mse_ds8_renders", &R::rel_mse_ds8_renders, csv_format::Numbers{}));
    s.push_back(column("flip_hdr_renders", &R::flip_hdr_renders, csv_format::Numbers{}));
    const Schema<R> denoised = quality_denoised_columns();
    s.insert(s.end(), denoised.begin(), denoised.end());
    s.push_back(column("render_device", &R::render_device, Text{}, Key::Yes));
    s.push_back(column("gpu_clock", &R::gpu_clock, Text{}));
    s.push_back(column("gpu_frame_ms", &R::gpu_frame_ms, G{}));
    return s;
  }();
  return schema;
}

}  // namespace raycoh
