// The page's drawing primitives (harness/report/report_parts.h): HTML escaping and base64 for the self-contained page,
// the figures' colours (Okabe & Ito's colour-blind-safe hues, shades of them, a blue ramp for heatmaps), SVG text and
// axis ticks. The figures that use them are report_figures.cpp.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "harness/report/report_parts.h"

namespace raycoh::report_detail {

std::string html_escape(const std::string& s) {
  std::string out;
  for (char ch : s) {
    if (ch == '&')
      out += "&amp;";
    else if (ch == '<')
      out += "&lt;";
    else if (ch == '>')
      out += "&gt;";
    else if (ch == '"')
      out += "&quot;";
    else
      out += ch;
  }
  return out;
}

std::string base64(const std::string& bytes) {
  static const char* t = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const uint32_t v = (uint8_t(bytes[i]) << 16) | (uint8_t(bytes[i + 1]) << 8) | uint8_t(bytes[i + 2]);
    out += {t[v >> 18], t[(v >> 12) & 63], t[(v >> 6) & 63], t[v & 63]};
  }
  if (i + 1 == bytes.size()) {
    const uint32_t v = uint8_t(bytes[i]) << 16;
    out += {t[v >> 18], t[(v >> 12) & 63], '=', '='};
  } else if (i + 2 == bytes.size()) {
    const uint32_t v = (uint8_t(bytes[i]) << 16) | (uint8_t(bytes[i + 1]) << 8);
    out += {t[v >> 18], t[(v >> 12) & 63], t[(v >> 6) & 63], '='};
  }
  return out;
}

// Okabe & Ito (2008), colour-blind safe; noopt (the baseline) is grey.
const char* const kHues[7] = {"#0072B2", "#E69F00", "#009E73", "#CC79A7", "#D55E00", "#56B4E9", "#F0E442"};

std::string generator_colour(const std::string& generator, const std::vector<std::string>& generators) {
  if (generator == "noopt") return "#666666";
  size_t i = 0;  // the same hue for a generator in every figure of a file, with or without the primary bound
  for (const std::string& g : generators) {
    if (g == generator) break;
    if (g != "noopt" && g != "primary") ++i;
  }
  return kHues[i % 7];
}

// The colour mixed with white: shade 0 is the colour itself, shade 1 almost white.
std::string lighten(const std::string& hex, double shade) {
  const int r = std::stoi(hex.substr(1, 2), nullptr, 16), g = std::stoi(hex.substr(3, 2), nullptr, 16),
            b = std::stoi(hex.substr(5, 2), nullptr, 16);
  auto mix = [&](int c) { return static_cast<int>(std::lround(c + (255 - c) * shade)); };
  return fmt::format("#{:02x}{:02x}{:02x}", mix(r), mix(g), mix(b));
}

// A light-to-dark blue ramp for heatmaps (t in [0, 1]).
std::string ramp(double t) {
  t = std::clamp(t, 0.0, 1.0);
  const int r = static_cast<int>(std::lround(239 + (8 - 239) * t)),
            g = static_cast<int>(std::lround(243 + (48 - 243) * t)),
            b = static_cast<int>(std::lround(255 + (107 - 255) * t));
  return fmt::format("#{:02x}{:02x}{:02x}", r, g, b);
}

std::string text(double x, double y, const std::string& s, const char* anchor, int size, const char* extra) {
  return fmt::format("<text x=\"{:.1f}\" y=\"{:.1f}\" text-anchor=\"{}\" font-size=\"{}\"{}>{}</text>\n", x, y, anchor,
                     size, extra, html_escape(s));
}

// "Nice" axis ticks from 0 to at least hi.
std::vector<double> ticks(double hi) {
  const double raw = hi / 5;
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  const double step = raw / mag < 2 ? 2 * mag : raw / mag < 5 ? 5 * mag : 10 * mag;
  std::vector<double> t;
  for (double v = 0; v < hi + step * 0.999; v += step) t.push_back(v);
  return t;
}

}  // namespace raycoh::report_detail
