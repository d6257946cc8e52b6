#include "shading/denoise.h"

#include <fmt/format.h>
#include <sys/wait.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <vector>

#include "core/error.h"
#include "shading/flip.h"

namespace raycoh {

namespace fs = std::filesystem;

Denoiser parse_denoiser(const std::string& option, const std::string& text) {
  if (text == "none") return Denoiser::None;
  if (text == "oidn") return Denoiser::Oidn;
  throw Error(fmt::format("{} {}: unknown denoiser; valid: none, oidn (Intel Open Image Denoise)", option, text));
}

const char* denoiser_name(Denoiser d) { return d == Denoiser::Oidn ? "oidn" : "none"; }

std::string oidn_program(const std::string& base) {
  const char* env = std::getenv("RAYCOH_OIDN");
  if (env && *env) return env;
  std::error_code ec;
  const fs::path linked = fs::path(base) / ".venv" / "bin" / "oidnDenoise";
  if (fs::is_regular_file(linked, ec)) return fs::absolute(linked).string();
  // pyoidn keeps the program inside its package: .venv/lib/python3.X/site-packages/pyoidn/oidn/bin.
  std::vector<fs::path> found;
  for (const auto& lib : fs::directory_iterator(fs::path(base) / ".venv" / "lib", ec)) {
    const fs::path p = lib.path() / "site-packages" / "pyoidn" / "oidn" / "bin" / "oidnDenoise";
    if (fs::is_regular_file(p, ec)) found.push_back(p);
  }
  std::sort(found.begin(), found.end());
  return found.empty() ? "" : fs::absolute(found.back()).string();
}

Image denoise_oidn(const std::string& program, const Image& color, const Image& albedo, const Image& normal,
                   const std::string& dir, const std::string& stem) {
  RAYCOH_CHECK(albedo.width == color.width && albedo.height == color.height && normal.width == color.width &&
                   normal.height == color.height,
               fmt::format("denoiser inputs of different sizes: colour {}x{}, albedo {}x{}, normal {}x{}", color.width,
                           color.height, albedo.width, albedo.height, normal.width, normal.height));
  const auto path = [&](const char* what) { return (fs::path(dir) / (stem + "-" + what + ".pfm")).string(); };
  const std::string c = path("color"), a = path("albedo"), n = path("normal"), out = path("denoised");
  write_pfm(color, c);
  write_pfm(albedo, a);
  write_pfm(normal, n);
  const std::string cmd = fmt::format("{} --hdr {} --alb {} --nrm {} -o {} >/dev/null 2>&1", shell_quoted(program),
                                      shell_quoted(c), shell_quoted(a), shell_quoted(n), shell_quoted(out));
  const int status = std::system(cmd.c_str());
  const int code = status == -1 ? -1 : WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  std::error_code ec;
  if (code != 0 || !fs::is_regular_file(out, ec))
    throw Error(fmt::format("denoiser {}: failed on {} (exit status {}); $RAYCOH_OIDN names another oidnDenoise",
                            program, c, code));
  Image denoised = read_pfm(out);
  for (const std::string& f : {c, a, n, out}) fs::remove(f, ec);
  if (denoised.width != color.width || denoised.height != color.height)
    throw Error(fmt::format("denoiser {}: wrote a {}x{} image for a {}x{} one ({})", program, denoised.width,
                            denoised.height, color.width, color.height, out));
  return denoised;
}

}  // namespace raycoh
