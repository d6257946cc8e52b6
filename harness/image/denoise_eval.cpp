#include "harness/image/denoise_eval.h"

#include <fmt/format.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>

namespace raycoh {

namespace fs = std::filesystem;

DenoiseEval::DenoiseEval(Denoiser denoiser) : denoiser_(denoiser) {
  if (denoiser_ == Denoiser::None) return;
  program_ = oidn_program();
  if (program_.empty()) return;
  dir_ = (fs::temp_directory_path() / fmt::format("raycoh-oidn-{}-{}", ::getpid(), static_cast<const void*>(this)))
             .string();
  fs::create_directories(dir_);
}

DenoiseEval::~DenoiseEval() {
  std::error_code ec;
  if (!dir_.empty()) fs::remove_all(dir_, ec);
}

void DenoiseEval::notice_if_missing() const {
  if (denoiser_ != Denoiser::None && program_.empty())
    std::fprintf(stderr,
                 "OIDN: not available (no $RAYCOH_OIDN, .venv/bin/oidnDenoise or pyoidn in .venv; scripts/setup "
                 "installs pyoidn), the denoised columns stay empty\n");
}

Image DenoiseEval::denoise(const Image& color, const AuxAccumulators& aux, double* seconds) const {
  const auto t0 = std::chrono::steady_clock::now();
  Image out = denoise_oidn(program_, color, aux.albedo.mean(), aux.normal.mean(), dir_, fmt::format("d{}", calls_++));
  if (seconds) *seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

void print_denoised_quality(const std::vector<QualityRow>& rows) {
  std::printf(
      "\nDenoised (%s): every render's mean denoised with its first-hit albedo and normal; relMSE ratio to the "
      "scene's first generator, raw and denoised\n\n| scene | generator | PSNR | denoised PSNR | relMSE | denoised "
      "relMSE | ratio raw | ratio denoised | denoised ds8 |\n|---|---|---:|---:|---:|---:|---:|---:|---:|\n",
      rows.empty() ? "oidn" : rows.front().denoise.c_str());
  const QualityRow* base = nullptr;
  for (const QualityRow& r : rows) {
    if (!base || base->scene != r.scene) base = &r;
    std::printf("| %s | %s | %.2f | %.2f | %.4g | %.4g | %.3f | %.3f | %.4g |\n", r.scene.c_str(), r.method.c_str(),
                r.psnr, r.denoised_psnr, r.rel_mse, r.denoised_rel_mse, r.rel_mse / base->rel_mse,
                r.denoised_rel_mse / base->denoised_rel_mse, r.denoised_rel_mse_ds8);
  }
}

}  // namespace raycoh
