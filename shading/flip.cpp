#include "shading/flip.h"

#include <fmt/format.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <optional>

namespace raycoh {

namespace fs = std::filesystem;

namespace {

// Standard output of a flip command (stderr dropped), or nothing when it cannot start or exits non-zero.
std::optional<std::string> flip_output(const std::string& cmd) {
  FILE* pipe = ::popen((cmd + " 2>/dev/null").c_str(), "r");
  if (!pipe) return std::nullopt;
  std::string text;
  char buf[256];
  while (std::fgets(buf, sizeof buf, pipe)) text += buf;
  if (::pclose(pipe) != 0) return std::nullopt;
  return text;
}

// The number flip prints after `label`, searching text from `from`, and where the label stands (npos: absent).
std::pair<double, size_t> flip_value(const std::string& text, const std::string& label, size_t from = 0) {
  const size_t at = text.find(label, from);
  return at == std::string::npos ? std::make_pair(std::nan(""), at)
                                 : std::make_pair(std::strtod(text.c_str() + at + label.size(), nullptr), at);
}

}  // namespace

std::string shell_quoted(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

std::string flip_program() {
  const char* env = std::getenv("RAYCOH_FLIP");
  if (env && *env) return env;
  std::error_code ec;
  const fs::path venv = fs::path(".venv") / "bin" / "flip";
  return fs::is_regular_file(venv, ec) ? fs::absolute(venv).string() : "";
}

double run_flip(const std::string& program, const std::string& ref, const std::string& test) {
  const auto text = flip_output(
      fmt::format("{} -r {} -t {} -v 1 -nerm", shell_quoted(program), shell_quoted(ref), shell_quoted(test)));
  return text ? flip_value(*text, "Mean:").first : std::nan("");
}

HdrFlip run_hdr_flip(const std::string& program, const std::string& ref, const std::vector<std::string>& tests,
                     const std::string& dir) {
  std::string cmd =
      fmt::format("{} -r {} -v 2 -nerm -nexm -d {} -t", shell_quoted(program), shell_quoted(ref), shell_quoted(dir));
  for (const std::string& t : tests) cmd += " " + shell_quoted(t);
  HdrFlip out;
  const auto text = flip_output(cmd);
  if (!text) return out;
  double sum = 0;
  size_t found = 0;
  for (size_t at = 0;;) {
    const auto [v, where] = flip_value(*text, "Mean:", at);
    if (where == std::string::npos) break;
    sum += v;
    ++found;
    out.per_test.push_back(v);
    at = where + 5;
  }
  if (found != tests.size()) return HdrFlip{};
  out.mean = sum / static_cast<double>(found);
  out.exposure =
      fmt::format("{:.4g}..{:.4g}/{:.0f}", flip_value(*text, "Start exposure:").first,
                  flip_value(*text, "Stop exposure:").first, flip_value(*text, "Number of exposures:").first);
  return out;
}

}  // namespace raycoh
