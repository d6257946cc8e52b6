// The denoised figures of `raycoh quality` and `raycoh converge` (`--denoise oidn`): the renders' running means are
// denoised by OIDN (shading/denoise.h) with the first-hit albedo and normal accumulated over the same frames
// (shading/path_tracer.h AuxAccumulators), and every error metric is computed on the denoised image against the same
// reference, beside the raw figures. When the oidnDenoise program is not found, one line says so and the denoised
// columns stay empty (as the FLIP columns do without flip).
#pragma once

#include <string>
#include <vector>

#include "records/quality_row.h"
#include "shading/denoise.h"
#include "shading/image.h"
#include "shading/path_tracer.h"

namespace raycoh {

class DenoiseEval {
 public:
  explicit DenoiseEval(Denoiser denoiser);
  ~DenoiseEval();
  DenoiseEval(const DenoiseEval&) = delete;
  DenoiseEval& operator=(const DenoiseEval&) = delete;
  Denoiser asked() const { return denoiser_; }
  // Asked for, and its program found: renders accumulate auxiliary images and are denoised.
  bool active() const { return denoiser_ != Denoiser::None && !program_.empty(); }
  // Prints the one line saying that the asked-for denoiser is missing (nothing when it is found or not asked for).
  void notice_if_missing() const;
  // The denoised image of `color` (the mean of the frames that aux holds too), and the seconds it took.
  Image denoise(const Image& color, const AuxAccumulators& aux, double* seconds = nullptr) const;
  const std::string& program() const { return program_; }

 private:
  Denoiser denoiser_;
  std::string program_, dir_;  // dir_: a temporary folder of this process for the program's files, removed after
  mutable int calls_ = 0;
};

// The console table of `quality --denoise`: raw and denoised PSNR and relMSE per scene and generator, with the
// relMSE ratio to the scene's first generator on both.
void print_denoised_quality(const std::vector<QualityRow>& rows);

}  // namespace raycoh
