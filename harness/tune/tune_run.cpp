#include "harness/tune/tune_run.h"

#include <fmt/format.h>

#include <algorithm>
#include <set>

#include "core/error.h"
#include "harness/image/quality.h"
#include "harness/image/render_common.h"
#include "harness/tune/tune_speed.h"

namespace raycoh {

namespace {

// Each image's fastest setting (settings that differ only in order share an image).
std::map<std::string, double> best_speed(const std::vector<TuneCandidate>& cs) {
  std::map<std::string, double> best;
  for (const TuneCandidate& c : cs) {
    const auto [it, fresh] = best.emplace(c.setting.image_spec(), c.speed);
    if (!fresh) it->second = std::max(it->second, c.speed);
  }
  return best;
}

// Image specs in the order the error stage measures them: the paper's default first (always measured, for the
// comparison), then by their fastest setting (fastest search) or as expanded (grid), each once.
std::vector<std::string> image_order(const TuneOptions& o, const std::vector<TuneCandidate>& cs) {
  std::vector<size_t> idx(cs.size());
  for (size_t i = 0; i < idx.size(); ++i) idx[i] = i;
  if (o.search == "fastest")
    std::stable_sort(idx.begin(), idx.end(), [&](size_t a, size_t b) { return cs[a].speed > cs[b].speed; });
  std::vector<std::string> out{paper_setting(o.generator).image_spec()};
  std::set<std::string> seen{out.front()};
  for (size_t i : idx)
    if (seen.insert(cs[i].setting.image_spec()).second) out.push_back(cs[i].setting.image_spec());
  return out;
}

QualityOptions error_options(const TuneOptions& o, const std::vector<std::string>& images) {
  QualityOptions q;
  q.common.tracer = o.error.tracer;
  q.common.device = o.error.device;
  q.common.width = o.width;
  q.common.height = o.height;
  q.common.seed = o.seed;
  q.common.max_depth = o.error.max_depth;
  q.common.rr_depth = o.error.rr_depth;
  q.common.force = o.force;
  q.scenes = {o.scene};
  q.generators = {{"noopt", ""}};
  for (const std::string& spec : images) q.generators.push_back(parse_plugin_spec(spec));
  q.frames = o.error.frames;
  q.ref_frames = o.error.ref_frames;
  q.bias_renders = o.error.seeds;
  q.cache_dir = o.error.cache_dir;
  q.out = tune_quality_path(o);
  q.image_dir = o.error.image_dir;
  q.shard = o.shard;
  q.console = false;
  return q;
}

// A candidate's error figures from its image's quality row against noopt's.
void fill_error(TuneCandidate& c, const QualityRow& row, const QualityRow& base) {
  c.error_measured = true;
  c.ds8 = paired_ratio(row.rel_mse_ds8_renders, base.rel_mse_ds8_renders);
  c.rel = paired_ratio(row.rel_mse_renders, base.rel_mse_renders);
  c.flip = paired_ratio(row.flip_hdr_renders, base.flip_hdr_renders);
  c.bias_verdict = row.bias_verdict;
  c.bias_share = row.bias_excluded;
  c.noopt_bias_share = base.bias_excluded;
  const double pixels = static_cast<double>(row.width) * row.height;
  // Two pixels of a tile of A pixels share a group in a frame with probability ~K / A (ours: groups shuffled every
  // frame), always for contiguous: their shares are correlated by at most that much.
  const double k = std::max(1, c.setting.k), area = static_cast<double>(c.setting.tile_w) * c.setting.tile_h;
  const double rho = c.setting.generator == "contiguous" ? 1.0 : std::min(1.0, k / area);
  c.share_units = pixels / (1 + (k - 1) * rho);
  c.noopt_units = pixels;
}

// The speed stage's figures into the candidates: the ranked and trace speeds, the ratios to noopt and to the
// paper's default with their intervals, and the waves each batch fills.
void take_speeds(const TuneOptions& o, const std::vector<TuneSetting>& settings, const TuneSpeeds& s, TuneMeasured& m) {
  m.scene = s.scene;
  m.tracer_label = s.tracer_label;
  m.speed_source = s.source;
  m.modeled = s.modeled;
  m.repeats = s.repeats;
  m.wave_rays = s.wave_rays;
  m.wave_basis = s.wave_basis;
  const bool whole = !s.by_method.empty();
  const TuneSpeed none;
  const TuneSpeed& noopt = whole ? s.by_method.at("noopt") : none;
  const TuneSpeed& paper = whole ? s.by_method.at(paper_setting(o.generator).spec()) : none;
  m.noopt_speed = noopt.ranked;
  for (const TuneSetting& setting : settings) {
    TuneCandidate c;
    c.setting = setting;
    if (whole) {
      const TuneSpeed& sp = s.by_method.at(setting.spec());
      c.speed = sp.ranked;
      c.trace_speed = sp.trace;
      c.to_noopt = tune_speed_ratio(noopt, sp);
      // The paper's default against itself: 1, no interval to state.
      c.to_paper = setting == paper_setting(o.generator) ? SpeedRatio{1, 1, 1, false} : tune_speed_ratio(paper, sp);
      if (s.wave_rays > 0) c.waves = sp.rays_per_frame / s.wave_rays;
    }
    m.candidates.push_back(c);
  }
}

}  // namespace

std::vector<std::string> tune_quality_methods(const std::string& space, const std::string& generator) {
  TuneOptions o;
  o.generator = generator;
  o.search = "grid";
  std::vector<TuneCandidate> cs;
  for (const TuneSetting& s : expand(parse_tune_space(space), generator)) {
    cs.emplace_back();
    cs.back().setting = s;
  }
  std::vector<std::string> methods{"noopt"};
  for (const std::string& image : image_order(o, cs)) methods.push_back(image);
  return methods;
}

std::string tune_speed_path(const TuneOptions& o) { return stem_path(o.out) + "-speed.csv"; }
std::string tune_quality_path(const TuneOptions& o) {
  return o.error.csv.empty() ? stem_path(o.out) + "-quality.csv" : o.error.csv;
}

std::optional<TuneMeasured> measure_tune(const TuneOptions& o, const TuneBudget& budget,
                                         const std::vector<TuneSetting>& settings, const Provenance& provenance) {
  TuneMeasured m;
  std::vector<std::string> methods;
  for (const TuneSetting& s : settings) methods.push_back(s.spec());
  take_speeds(o, settings,
              o.speed.csv.empty() ? measure_tune_speeds(o, methods, o.seed, tune_speed_path(o), provenance)
                                  : read_tune_speeds(o, o.speed.csv, methods, "--speed-csv"),
              m);
  std::vector<TuneCandidate>& cs = m.candidates;
  QualityOptions q = error_options(o, image_order(o, cs));
  std::fprintf(stderr, "tune: error of up to %zu images and noopt (%d seeds x %d frames, %s search) -> %s\n",
               q.generators.size() - 1, o.error.seeds, o.error.frames, o.search.c_str(), q.out.c_str());
  // Fastest search: stop once a measured image meets the budget at a speed no unmeasured image can beat.
  const std::map<std::string, double> best = best_speed(cs);
  std::set<std::string> unmeasured;
  for (size_t i = 1; i < q.generators.size(); ++i) unmeasured.insert(q.generators[i].text());
  double passing = -1;
  q.after_row = [&](const QualityRow& row) {
    if (!o.speed.csv.empty() && row.scene != m.scene)
      throw Error(fmt::format("--speed-csv {}: its speeds are of scene {}, --scene {} is {}", o.speed.csv, m.scene,
                              o.scene, row.scene));
    m.rows[row.method] = row;
    unmeasured.erase(row.method);
    if (o.search != "fastest" || row.method == "noopt" || !m.rows.count("noopt")) return false;
    // The candidates judged as the final decision judges them: each with its own setting (K enters the bias test).
    auto judged = [&](const TuneSetting& setting) {
      TuneCandidate c =
          *std::find_if(cs.begin(), cs.end(), [&](const TuneCandidate& x) { return x.setting == setting; });
      if (m.rows.count(setting.image_spec())) fill_error(c, m.rows.at(setting.image_spec()), m.rows.at("noopt"));
      return c;
    };
    const auto row_setting = std::find_if(cs.begin(), cs.end(),
                                          [&](const TuneCandidate& c) { return c.setting.image_spec() == row.method; });
    const TuneCandidate probe = judged(row_setting->setting), paper = judged(paper_setting(o.generator));
    const TuneBudget resolved = resolve_paper(budget, paper.error_measured ? &paper : nullptr);
    if (judge(probe, resolved).pass) passing = std::max(passing, best.at(row.method));
    double rest = -1;
    for (const std::string& u : unmeasured) rest = std::max(rest, best.at(u));
    return passing >= 0 && passing >= rest;
  };
  run_quality(q, provenance);
  if (!o.shard.whole()) return std::nullopt;
  const QualityRow& base = m.rows.at("noopt");
  for (TuneCandidate& c : cs)
    if (m.rows.count(c.setting.image_spec())) fill_error(c, m.rows.at(c.setting.image_spec()), base);
  return m;
}

}  // namespace raycoh
