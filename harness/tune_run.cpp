#include "harness/tune_run.h"

#include <fmt/format.h>

#include <algorithm>
#include <set>

#include "core/error.h"
#include "harness/experiment.h"
#include "harness/quality.h"
#include "harness/render_common.h"
#include "records/experiment_sums.h"
#include "records/result_csv.h"

namespace raycoh {

namespace {

ExperimentOptions speed_options(const TuneOptions& o, const std::vector<TuneSetting>& settings) {
  ExperimentOptions e;
  e.scenes = {o.scene};
  e.methods = {{"noopt", {"noopt", ""}}};
  for (const TuneSetting& s : settings) e.methods.push_back({s.spec(), parse_plugin_spec(s.spec())});
  e.tracers = {o.tracer};
  e.width = o.width;
  e.height = o.height;
  e.frames = o.speed_frames;
  e.seed = o.seed;
  e.repeats = o.repeats;
  e.out = tune_speed_path(o);
  e.force = o.force;
  e.shard = o.shard;
  return e;
}

struct Speed {
  double ranked = 0, trace = 0;
};

Speed speed_of(const Accumulated& a, const std::string& rank) {
  Speed s;
  s.trace = a.has_model ? a.modeled_mray_s() : a.mray_s();
  const double e2e = a.has_model ? a.modeled_e2e_mray_s() : a.on_device ? a.gpu_span_mray_s() : a.e2e_mray_s();
  s.ranked = rank == "trace" ? s.trace : e2e;
  return s;
}

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
  q.common.tracer = o.render_tracer;
  q.common.width = o.width;
  q.common.height = o.height;
  q.common.seed = o.seed;
  q.common.max_depth = o.max_depth;
  q.common.rr_depth = o.rr_depth;
  q.common.force = o.force;
  q.scenes = {o.scene};
  q.generators = {{"noopt", ""}};
  for (const std::string& spec : images) q.generators.push_back(parse_plugin_spec(spec));
  q.frames = o.frames;
  q.ref_frames = o.ref_frames;
  q.bias_renders = o.seeds;
  q.cache_dir = o.cache_dir;
  q.out = tune_quality_path(o);
  q.image_dir = o.image_dir;
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

// --speed-csv: noopt's and every setting's speed from an experiment CSV measured elsewhere.
void speeds_from_file(const TuneOptions& o, const std::vector<TuneSetting>& settings, TuneMeasured& m) {
  const ResultCsv c = read_result_csv(o.speed_csv);
  const ResultKind kind = result_kind(c);
  if (kind != ResultKind::Table && kind != ResultKind::Sweep)
    throw Error(
        fmt::format("--speed-csv {}: not a table or sweep CSV (a tune's <stem>-speed.csv is one)", o.speed_csv));
  const Experiment e = read_experiment(c);
  const std::string res = fmt::format("{}×{}", o.width, o.height);
  if (e.scenes.size() != 1 || e.tracers.size() != 1 || e.resolutions != std::set<std::string>{res})
    throw Error(
        fmt::format("--speed-csv {}: needs one scene, one tracer and --res {}x{}; it holds {} scene(s), {} "
                    "tracer(s), resolution(s) {}",
                    o.speed_csv, o.width, o.height, e.scenes.size(), e.tracers.size(), join_set(e.resolutions)));
  m.scene = e.scenes.front();
  m.tracer_label = e.tracers.front();
  m.modeled = e.modeled.at(m.tracer_label);
  m.speed_source = o.speed_csv;
  const auto& sums = e.sums.at(m.scene).at(m.tracer_label);
  auto speed = [&](const std::string& method) {
    const auto it = sums.find(method);
    if (it == sums.end())
      throw Error(fmt::format("--speed-csv {}: no rows of {}; measure the same space there (raycoh tune --tracer ...)",
                              o.speed_csv, method));
    const Sums& s = it->second;
    const double trace = s.speed(m.modeled, false);
    const double e2e = m.modeled          ? s.speed(true, true)
                       : s.gpu_e2e_ms > 0 ? s.rays / s.gpu_e2e_ms * 1e-3
                                          : s.speed(false, true);
    return Speed{o.rank == "trace" ? trace : e2e, trace};
  };
  m.noopt_speed = speed("noopt").ranked;
  for (const TuneSetting& s : settings) {
    const Speed sp = speed(s.spec());
    m.candidates.push_back({s, sp.ranked, sp.trace, false, {}, {}, {}, ""});
  }
}

// This run's speed stage (resumed from <stem>-speed.csv where it holds rows).
void measure_speeds(const TuneOptions& o, const std::vector<TuneSetting>& settings, const Provenance& provenance,
                    TuneMeasured& m) {
  const ExperimentOptions e = speed_options(o, settings);
  std::fprintf(stderr, "tune: speed of %zu settings and noopt (%s) -> %s\n", settings.size(), o.tracer.text().c_str(),
               e.out.c_str());
  const std::vector<SceneResult> results = run_experiment(e, provenance);
  m.speed_source = e.out;
  std::vector<TuneCandidate>& cs = m.candidates;
  if (!results.empty() && o.shard.whole()) {
    const SceneResult& r = results.front();
    m.scene = r.scene;
    m.tracer_label = r.tracer_labels.front();
    const auto& by_method = r.by_tracer.at(m.tracer_label);
    m.modeled = by_method.at("noopt").has_model;
    m.noopt_speed = speed_of(by_method.at("noopt"), o.rank).ranked;
    for (const TuneSetting& s : settings) {
      const Speed sp = speed_of(by_method.at(s.spec()), o.rank);
      cs.push_back({s, sp.ranked, sp.trace, false, {}, {}, {}, ""});
    }
  } else {
    for (const TuneSetting& s : settings) cs.push_back({s, 0, 0, false, {}, {}, {}, ""});
  }
}

}  // namespace

std::vector<std::string> tune_quality_methods(const std::string& space, const std::string& generator) {
  TuneOptions o;
  o.generator = generator;
  o.search = "grid";
  std::vector<TuneCandidate> cs;
  for (const TuneSetting& s : expand(parse_tune_space(space), generator))
    cs.push_back({s, 0, 0, false, {}, {}, {}, ""});
  std::vector<std::string> methods{"noopt"};
  for (const std::string& image : image_order(o, cs)) methods.push_back(image);
  return methods;
}

std::string tune_speed_path(const TuneOptions& o) { return stem_path(o.out) + "-speed.csv"; }
std::string tune_quality_path(const TuneOptions& o) {
  return o.quality_csv.empty() ? stem_path(o.out) + "-quality.csv" : o.quality_csv;
}

std::optional<TuneMeasured> measure_tune(const TuneOptions& o, const TuneBudget& budget,
                                         const std::vector<TuneSetting>& settings, const Provenance& provenance) {
  TuneMeasured m;
  if (o.speed_csv.empty())
    measure_speeds(o, settings, provenance, m);
  else
    speeds_from_file(o, settings, m);
  std::vector<TuneCandidate>& cs = m.candidates;
  QualityOptions q = error_options(o, image_order(o, cs));
  std::fprintf(stderr, "tune: error of up to %zu images and noopt (%d seeds x %d frames, %s search) -> %s\n",
               q.generators.size() - 1, o.seeds, o.frames, o.search.c_str(), q.out.c_str());
  // Fastest search: stop once a measured image meets the budget at a speed no unmeasured image can beat.
  const std::map<std::string, double> best = best_speed(cs);
  std::set<std::string> unmeasured;
  for (size_t i = 1; i < q.generators.size(); ++i) unmeasured.insert(q.generators[i].text());
  double passing = -1;
  q.after_row = [&](const QualityRow& row) {
    if (!o.speed_csv.empty() && row.scene != m.scene)
      throw Error(fmt::format("--speed-csv {}: its speeds are of scene {}, --scene {} is {}", o.speed_csv, m.scene,
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
