#include "records/converge_row.h"

#include <filesystem>

namespace raycoh {

const Schema<ConvergeRow>& converge_schema() {
  using namespace csv_format;
  using R = ConvergeRow;
  using G = GeneralOrEmpty;
  static const Schema<R> schema = [] {
    Schema<R> s = {
        column("scene", &R::scene, Text{}),
        column("scene_spec", &R::scene_spec, Text{}),
        column("scene_fingerprint", &R::scene_fingerprint, Text{}),
        column("method", &R::method, Text{}),
        column("generator", &R::generator, Text{}),
        column("generator_params", &R::generator_params, Text{}),
        column("tracer", &R::tracer, Text{}),
        column("tracer_params", &R::tracer_params, Text{}),
        column("width", &R::width, Integer<int>{}),
        column("height", &R::height, Integer<int>{}),
        column("seed", &R::seed, Integer<uint32_t>{}),
        column("ref_frames", &R::ref_frames, Optional<Integer<int>>{}),
        column("max_depth", &R::max_depth, Integer<int>{}),
        column("rr_depth", &R::rr_depth, Integer<int>{}),
        column("tone_map", &R::tone_map, Text{}),
        column("reference", &R::reference, Text{}),
        column("protocol", &R::protocol, Text{}),
        column("metrics", &R::metrics, Text{}),
        column("frame", &R::frame, Integer<int>{}),
        column("wall_s", &R::wall_s, G{}),
        column("trace_s", &R::trace_s, G{}),
        column("gen_s", &R::gen_s, G{}),
        column("frame_wall_ms", &R::frame_wall_ms, G{}),
        column("frame_trace_ms", &R::frame_trace_ms, G{}),
        column("rays", &R::rays, Integer<uint64_t>{}),
        column("rel_mse", &R::rel_mse, G{}),
        column("mse", &R::mse, G{}),
        column("rmse", &R::rmse, G{}),
        column("psnr", &R::psnr, G{}),
        column("ssim", &R::ssim, G{}),
        column("ref_noise_mse", &R::ref_noise_mse, G{}),
        column("ref_noise_rel_mse", &R::ref_noise_rel_mse, G{}),
        column("ref_noise_share", &R::ref_noise_share, G{}),
        column("mse_corr", &R::mse_corr, G{}),
        column("rel_mse_corr", &R::rel_mse_corr, G{}),
        column("psnr_corr", &R::psnr_corr, G{}),
        column("non_finite_samples", &R::non_finite_samples, Integer<uint64_t>{}),
        column("gpu_model", &R::gpu_model, Text{}),
        column("modeled_frame", &R::modeled_frame, Optional<Integer<int>>{}),
        column("frame_modeled_gen_ms", &R::frame_modeled_gen_ms, G{}),
        column("frame_modeled_trace_ms", &R::frame_modeled_trace_ms, G{}),
        column("frame_modeled_gpu_ms", &R::frame_modeled_gpu_ms, G{}),
        column("modeled_gpu_s", &R::modeled_gpu_s, G{}),
    };
    append_columns(s, provenance_schema(), &R::provenance);
    append_columns(s, recorded_schema(), &R::recorded);
    s.push_back(column("gpu_preset", &R::gpu_preset, Text{}));
    s.push_back(column("denoise", &R::denoise, Text{}));
    s.push_back(column("denoised_rel_mse", &R::denoised_rel_mse, G{}));
    s.push_back(column("denoised_mse", &R::denoised_mse, G{}));
    s.push_back(column("denoised_rmse", &R::denoised_rmse, G{}));
    s.push_back(column("denoised_psnr", &R::denoised_psnr, G{}));
    s.push_back(column("denoised_ssim", &R::denoised_ssim, G{}));
    s.push_back(column("denoised_mse_corr", &R::denoised_mse_corr, G{}));
    s.push_back(column("denoised_rel_mse_corr", &R::denoised_rel_mse_corr, G{}));
    s.push_back(column("denoised_psnr_corr", &R::denoised_psnr_corr, G{}));
    s.push_back(column("denoise_ms", &R::denoise_ms, G{}));
    s.push_back(column("render_device", &R::render_device, Text{}));
    s.push_back(column("gpu_clock", &R::gpu_clock, Text{}));
    s.push_back(column("frame_gpu_ms", &R::frame_gpu_ms, G{}));
    s.push_back(column("gpu_s", &R::gpu_s, G{}));
    append_columns(s, device_stage_schema(), &R::frame_gpu_stages);
    return s;
  }();
  return schema;
}

const Schema<SummaryRow>& summary_schema() {
  using namespace csv_format;
  using R = SummaryRow;
  using G = GeneralOrEmpty;
  static const Schema<R> schema = [] {
    Schema<R> s = {
        column("scene", &R::scene, Text{}),
        column("method", &R::method, Text{}),
        column("baseline", &R::baseline, Text{}),
        column("metric", &R::metric, Text{}),
        column("clock", &R::clock, Text{}),
        column("horizon_s", &R::horizon_s, G{}),
        column("error", &R::error, G{}),
        column("baseline_error", &R::baseline_error, G{}),
        column("equal_time_error_ratio", &R::equal_time_error_ratio, G{}),
        column("target_error", &R::target_error, G{}),
        column("time_s", &R::time_s, G{}),
        column("baseline_time_s", &R::baseline_time_s, G{}),
        column("equal_error_speedup", &R::equal_error_speedup, G{}),
        column("ref_noise_rel_mse", &R::ref_noise_rel_mse, G{}),
        column("ref_noise_share", &R::ref_noise_share, G{}),
        column("ref_noise_residual_share", &R::ref_noise_residual_share, G{}),
        column("error_corr", &R::error_corr, G{}),
        column("baseline_error_corr", &R::baseline_error_corr, G{}),
        column("equal_time_error_ratio_corr", &R::equal_time_error_ratio_corr, G{}),
        column("frames", &R::frames, Integer<int>{}),
        column("baseline_frames", &R::baseline_frames, Integer<int>{}),
    };
    append_columns(s, provenance_schema(), &R::provenance);
    s.push_back(column("render_device", &R::render_device, Text{}));
    return s;
  }();
  return schema;
}

std::string converge_summary_path(const std::string& out) {
  const std::filesystem::path p(out);
  return ((p.parent_path() / p.stem()).string()) + "-summary.csv";
}

}  // namespace raycoh
