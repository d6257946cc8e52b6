// Denoising with Intel Open Image Denoise 2.x (OIDN) through its `oidnDenoise` program, which PyPI's `pyoidn` ships
// with the library for the CPU (scripts/setup installs it into .venv and links .venv/bin/oidnDenoise): the one adapter
// of the denoised columns of `raycoh quality` and `raycoh converge` (`--denoise oidn`), found and run like ꟻLIP
// (shading/flip.h).
//
// What OIDN is given (its API documentation, filter "RT"): the linear HDR colour (`--hdr`, values in [0, inf); the
// input scale is left to OIDN, which derives it from the image, so no exposure is passed), the albedo (three
// channels in [0, 1]) and the shading normal (world space, values in [-1, 1]) of the *first hit* per pixel, each as
// a PFM file. The auxiliary images are the mean over the same frames as the colour, through the same jittered camera
// rays (path_tracer.h aux_of): anti-aliased like the colour, as OIDN asks, but not noise-free at one frame, so they
// are passed as noisy (OIDN's `cleanAux` off, its default). Pixels whose camera ray missed get albedo and normal 0
// (OIDN's "no surface here").
#pragma once

#include <string>

#include "shading/image.h"

namespace raycoh {

enum class Denoiser { None, Oidn };

// "none" | "oidn"; throws raycoh::Error naming `option` and the valid choices.
Denoiser parse_denoiser(const std::string& option, const std::string& text);
const char* denoiser_name(Denoiser d);

// $RAYCOH_OIDN, else .venv/bin/oidnDenoise in `base` (the working folder), else the program inside .venv's pyoidn
// package (.venv/lib/python3*/site-packages/pyoidn/oidn/bin/oidnDenoise); "" when none exists.
std::string oidn_program(const std::string& base = ".");

// The denoised colour: colour, albedo and normal written as PFM files into `dir` (which must exist) under `stem`,
// oidnDenoise run on them, its output read back. Throws raycoh::Error naming the program and the exit status when it
// fails or writes no image of the colour's size. Images must all have one size.
Image denoise_oidn(const std::string& program, const Image& color, const Image& albedo, const Image& normal,
                   const std::string& dir, const std::string& stem);

}  // namespace raycoh
