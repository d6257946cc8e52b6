// `raycoh tune` (harness/tune/tune.h): options, the decision's rows and the console. The stages are tune_run.cpp's.
#include "harness/tune/tune.h"

#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <fstream>

#include "core/error.h"
#include "harness/common/cli.h"
#include "harness/common/command.h"
#include "harness/image/render_device.h"
#include "harness/tune/tune_confirm.h"
#include "harness/tune/tune_run.h"
#include "oiio/image_codec.h"
#include "records/record_csv.h"
#include "records/tune_row.h"
#include "shading/flip.h"
#include "tracers/hw_counters.h"

namespace raycoh {

namespace {

void check_tune(const TuneOptions& o, const TuneBudget& b) {
  if (o.generator != "ours" && o.generator != "contiguous")
    throw Error(fmt::format("--generator {}: tune searches the settings of ours or contiguous", o.generator));
  if (o.search != "fastest" && o.search != "grid")
    throw Error(fmt::format("--search {}: valid: fastest, grid", o.search));
  if (o.speed.rank != "e2e" && o.speed.rank != "trace")
    throw Error(fmt::format("--rank {}: valid: e2e, trace", o.speed.rank));
  if (o.error.seeds < 2 || o.error.seeds > 256)
    throw Error(fmt::format("--seeds {}: must be in [2, 256] (the error ratios' spread needs two)", o.error.seeds));
  check_device(o.error.device, "--render-device");
  if (o.speed.frames < 1 || o.speed.frames > 1000)
    throw Error(fmt::format("--speed-frames {}: must be in [1, 1000]", o.speed.frames));
  if (!o.shard.whole() && o.search != "grid")
    throw Error(
        fmt::format("--shard {}: needs --search grid (the fastest search depends on every speed)", o.shard.text()));
  if (o.speed.confirm < 0 || o.speed.confirm > kMaxConfirmSeeds)
    throw Error(fmt::format("--confirm {}: must be in [1, {}] (fresh seeds to re-measure the speed call on)",
                            o.speed.confirm, kMaxConfirmSeeds));
  if (o.speed.confirm > 0 && (!o.speed.csv.empty() || !o.shard.whole()))
    throw Error(
        fmt::format("--confirm {}: needs this run's own speed stage (not --speed-csv, not --shard)", o.speed.confirm));
  if (b.flip > 0 && (flip_program().empty() || !image_io_available()))
    throw Error(fmt::format(
        "--budget flip={}: HDR-FLIP needs the flip program ($RAYCOH_FLIP or .venv/bin/flip: scripts/setup) and a "
        "build with EXR; leave flip out of the budget",
        b.flip));
}

// <out> is derived from the stages' files and rewritten by every run; a file there that is not a tune CSV is
// another result, kept unless --force.
void refuse_foreign_out(const TuneOptions& o) {
  std::ifstream in(o.out);
  std::string header;
  if (!in || o.force || !std::getline(in, header)) return;
  // A tune CSV of an earlier revision (fewer columns) is still a tune CSV.
  const std::string start = "scene,scene_spec,setting,generator,";
  if (header.rfind(start, 0) != 0 || header.find(",meets_budget,") == std::string::npos)
    throw Error(fmt::format("--out {}: exists and is not a tune CSV; choose another path or --force", o.out));
}

TuneRow row_of(const TuneOptions& o, const TuneBudget& b, const TuneMeasured& m, const TuneChoice& ch, size_t i,
               const Provenance& p) {
  const TuneCandidate& c = m.candidates[i];
  const TuneSetting& s = c.setting;
  TuneRow r;
  r.scene_spec = o.scene;
  r.scene = m.scene;
  r.setting = s.spec();
  r.generator = s.generator;
  r.tile_w = s.tile_w, r.tile_h = s.tile_h, r.k = s.k;
  r.order = s.order, r.hybrid = s.hybrid, r.frame = s.frame;
  r.tracer_spec = m.tracer_label;
  r.speed_csv = m.speed_source;
  r.speed_kind = m.modeled ? "modeled" : "measured";
  r.rank = o.speed.rank;
  r.mray_s = c.speed;
  r.speedup = m.noopt_speed > 0 ? c.speed / m.noopt_speed : std::nan("");
  r.trace_mray_s = c.trace_speed;
  r.e2e_mray_s = o.speed.rank == "e2e" ? c.speed : std::nan("");
  r.noopt_mray_s = m.noopt_speed;
  r.speedup_lo = c.to_noopt.has_interval ? c.to_noopt.lo : std::nan("");
  r.speedup_hi = c.to_noopt.has_interval ? c.to_noopt.hi : std::nan("");
  r.vs_paper = c.to_paper.ratio > 0 ? c.to_paper.ratio : std::nan("");
  r.vs_paper_lo = c.to_paper.has_interval ? c.to_paper.lo : std::nan("");
  r.vs_paper_hi = c.to_paper.has_interval ? c.to_paper.hi : std::nan("");
  r.vs_paper_verdict = c.to_paper.ratio > 0 && !(s == paper_setting(o.generator)) ? speed_verdict(c.to_paper) : "";
  r.speed_repeats = m.repeats;
  r.waves = c.waves;
  r.fastest_passing = ch.fastest_passing == static_cast<int>(i);
  r.render_tracer = o.error.tracer.text();
  r.render_device = o.error.device;
  r.width = o.width, r.height = o.height, r.frames = o.error.frames, r.ref_frames = o.error.ref_frames,
  r.seeds = o.error.seeds;
  r.seed = o.seed;
  r.error_measured = c.error_measured;
  std::tie(r.ds8, r.ds8_lo, r.ds8_hi) = std::make_tuple(c.ds8.mean, c.ds8.lo, c.ds8.hi);
  std::tie(r.rel, r.rel_lo, r.rel_hi) = std::make_tuple(c.rel.mean, c.rel.lo, c.rel.hi);
  std::tie(r.flip, r.flip_lo, r.flip_hi) = std::make_tuple(c.flip.mean, c.flip.lo, c.flip.hi);
  r.bias_verdict = c.bias_verdict;
  r.budget = describe(b);
  r.meets_budget = ch.verdicts[i].pass;
  r.front = ch.front[i];
  r.recommended = ch.recommended == static_cast<int>(i);
  r.closest_miss = ch.closest_miss == static_cast<int>(i);
  r.paper_default = s == paper_setting(o.generator);
  r.reason = ch.verdicts[i].reason;
  r.search = o.search;
  r.provenance = p;
  return r;
}

std::string ratio_text(double mean, double lo, double hi) {
  return std::isnan(mean) ? "—" : fmt::format("{:.3f} [{:.3f}, {:.3f}]", mean, lo, hi);
}

// A speed ratio as the table prints it: "1.23x [1.18, 1.30]", or "1.23x" without an interval.
std::string speed_text(double ratio, double lo, double hi) {
  if (std::isnan(ratio)) return "—";
  return std::isnan(lo) ? fmt::format("{:.2f}x", ratio) : fmt::format("{:.2f}x [{:.2f}, {:.2f}]", ratio, lo, hi);
}

void print_row(const TuneRow& r) {
  std::string marks;
  if (r.recommended) marks += " **recommended**";
  if (r.fastest_passing && !r.recommended) marks += " fastest within budget";
  if (r.closest_miss) marks += " closest miss";
  if (r.paper_default) marks += " paper default";
  if (r.front) marks += " front";
  std::printf("| %dx%d | %d | %s | %s | %s | %.1f | %s | %s | %s | %s | %s | %s | %s | %s |%s |\n", r.tile_w, r.tile_h,
              r.k, r.order.c_str(), r.hybrid.c_str(), r.frame.c_str(), r.mray_s,
              speed_text(r.speedup, r.speedup_lo, r.speedup_hi).c_str(),
              speed_text(r.vs_paper, r.vs_paper_lo, r.vs_paper_hi).c_str(),
              std::isnan(r.waves) ? "—" : fmt::format("{:.2f}", r.waves).c_str(),
              ratio_text(r.ds8, r.ds8_lo, r.ds8_hi).c_str(), ratio_text(r.rel, r.rel_lo, r.rel_hi).c_str(),
              ratio_text(r.flip, r.flip_lo, r.flip_hi).c_str(), r.bias_verdict.empty() ? "—" : r.bias_verdict.c_str(),
              !r.error_measured ? "—"
              : r.meets_budget  ? "yes"
                                : r.reason.c_str(),
              marks.c_str());
}

// How full the GPU is: one line, a warning below two waves (a batch that does not fill the GPU twice over is
// timed in its ramp and tail, and its ranks may not carry to a full frame).
void print_waves(const TuneMeasured& m, const std::vector<TuneRow>& rows) {
  if (m.wave_rays <= 0) {
    if (m.tracer_label.rfind("cuda", 0) == 0)
      std::printf("\nWaves: unknown (the GPU that measured these speeds is not this machine's, or none is here).\n");
    return;
  }
  double least = INFINITY;
  for (const TuneRow& r : rows) least = std::min(least, r.waves);
  if (least < 2)
    std::printf(
        "\nWarning: the batch fills %.2f waves of the GPU (%s), fewer than 2: too small to fill the GPU: speed ranks "
        "may not carry to a full frame.\n",
        least, m.wave_basis.c_str());
  else
    std::printf("\nWaves: the batch fills %.1f waves of the GPU (%s).\n", least, m.wave_basis.c_str());
}

// The speed call on the recommendation (harness/tune/tune_select.h settle_speed).
void print_speed_call(const TuneOptions& o, const TuneMeasured& m, const TuneRow& rec, const TuneRow* fastest,
                      const TuneRow* paper) {
  const char* speed = o.speed.rank == "e2e" ? "end-to-end" : "trace";
  if (fastest && fastest != &rec) {
    std::printf(
        "\nFastest within the budget: %s — %s the paper's default (8x8, K = 8): %s at %.0f%%, so the paper's "
        "default is kept.\n",
        fastest->setting.c_str(), speed_text(fastest->vs_paper, fastest->vs_paper_lo, fastest->vs_paper_hi).c_str(),
        fastest->vs_paper_verdict.c_str(), 100 * kSpeedConfidence);
  }
  std::printf("\nRecommended: %s — %s noopt's %s speed%s", rec.setting.c_str(),
              speed_text(rec.speedup, rec.speedup_lo, rec.speedup_hi).c_str(), speed, m.modeled ? " (MODELED)" : "");
  if (paper && !rec.paper_default) {
    const std::string call = rec.vs_paper_verdict == "no interval"
                                 ? "no interval (one modeled run: its point figure)"
                                 : fmt::format("{} at {:.0f}%", rec.vs_paper_verdict, 100 * kSpeedConfidence);
    std::printf(", %s the paper's default (8x8, K = 8), which %s; against it: %s",
                speed_text(rec.vs_paper, rec.vs_paper_lo, rec.vs_paper_hi).c_str(),
                paper->meets_budget ? "meets the budget too" : ("misses it: " + paper->reason).c_str(), call.c_str());
  } else if (rec.paper_default) {
    std::printf(", the paper's default (8x8, K = 8)");
  }
  std::printf(".\n");
  if (rec.speedup < 1)
    std::printf("It is slower than noopt (%.2fx): no setting within the budget pays here; keep noopt.\n", rec.speedup);
}

// The settings by speed; settings without error figures are summed up in one line.
void print_tune(const TuneOptions& o, const TuneMeasured& m, std::vector<TuneRow> rows) {
  std::stable_sort(rows.begin(), rows.end(), [](const TuneRow& a, const TuneRow& b) { return a.mray_s > b.mray_s; });
  const TuneRow& any = rows.front();
  const std::string repeats = m.modeled ? "one MODELED run each: no interval"
                              : m.repeats > 1
                                  ? fmt::format("{} repeats each; speed ratios with their {:.0f}% paired interval",
                                                m.repeats, 100 * kSpeedConfidence)
                                  : "one repeat each: no interval";
  std::printf(
      "\n%s: tune of %s, %dx%d. Speed: %s%s %s MRay/s (noopt %.1f), %d frame(s), %s. Error: ratio to noopt's with "
      "its 95%% interval over %d seeds of %d frames each, against a %d-frame NoOpt reference (%s). Budget %s; "
      "%s search.\n\n| tile | K | order | hybrid | frame | MRay/s | × noopt | × paper | waves | ds8 | rel | HDR-FLIP | "
      "bias | meets budget | |\n|---|---:|---|---|---|---:|---:|---:|---:|---:|---:|---:|---|---|---|\n",
      m.scene.c_str(), o.generator.c_str(), o.width, o.height, m.modeled ? "MODELED by " : "measured on ",
      m.tracer_label.c_str(), o.speed.rank == "e2e" ? "end-to-end" : "trace", m.noopt_speed, o.speed.frames,
      repeats.c_str(), o.error.seeds, o.error.frames, o.error.ref_frames, o.error.tracer.text().c_str(),
      any.budget.c_str(), o.search.c_str());
  size_t skipped = 0;
  for (const TuneRow& r : rows)
    if (r.error_measured || r.paper_default)
      print_row(r);
    else
      ++skipped;
  if (skipped > 0)
    std::printf("\n%zu slower setting(s) left unmeasured by the fastest search (--search grid measures them).\n",
                skipped);
  print_waves(m, rows);
  auto find = [&](auto pred) {
    const auto it = std::find_if(rows.begin(), rows.end(), pred);
    return it == rows.end() ? nullptr : &*it;
  };
  const TuneRow* rec = find([](const TuneRow& r) { return r.recommended; });
  if (rec) {
    print_speed_call(o, m, *rec, find([](const TuneRow& r) { return r.fastest_passing; }),
                     find([](const TuneRow& r) { return r.paper_default; }));
  } else {
    const TuneRow* miss = find([](const TuneRow& r) { return r.closest_miss; });
    std::printf("\nNo setting meets the budget; keep noopt.%s\n",
                !miss
                    ? ""
                    : fmt::format(" Closest miss: {} ({:.2f}x noopt): {}.", miss->setting, miss->speedup, miss->reason)
                          .c_str());
  }
}

}  // namespace

int run_tune(const TuneOptions& o, const Provenance& provenance) {
  const TuneBudget budget = parse_tune_budget(o.error.budget);
  std::vector<TuneSetting> settings = expand(parse_tune_space(o.space), o.generator);
  check_tune(o, budget);
  if (const std::string why = hw_counters_refusal("--tracer", o.speed.tracer.params); !why.empty()) throw Error(why);
  // The paper's default is always measured: the recommendation's gain is stated against it.
  if (std::find(settings.begin(), settings.end(), paper_setting(o.generator)) == settings.end())
    settings.push_back(paper_setting(o.generator));
  const std::optional<TuneMeasured> m = measure_tune(o, budget, settings, provenance);
  if (!m) {
    std::printf(
        "Wrote shard %s of the tune to %s and %s (%s); join each with the other shards' (raycoh merge), then run "
        "the same tune command without --shard for the decision\n",
        o.shard.text().c_str(), tune_speed_path(o).c_str(), tune_quality_path(o).c_str(),
        provenance.git_revision.c_str());
    return 0;
  }
  const auto paper = std::find_if(m->candidates.begin(), m->candidates.end(),
                                  [&](const TuneCandidate& c) { return c.setting == paper_setting(o.generator); });
  const TuneBudget resolved = resolve_paper(budget, paper == m->candidates.end() ? nullptr : &*paper);
  TuneChoice choice = choose(m->candidates, resolved);
  const int paper_index = paper == m->candidates.end() ? -1 : static_cast<int>(paper - m->candidates.begin());
  settle_speed(choice, m->candidates, paper_index);
  std::vector<TuneRow> rows;
  for (size_t i = 0; i < m->candidates.size(); ++i) rows.push_back(row_of(o, budget, *m, choice, i, provenance));
  refuse_foreign_out(o);
  RecordCsv<TuneRow> csv(o.out, tune_schema(), CsvWriter::Options::once(true));
  for (const TuneRow& r : rows) csv.write(r);
  csv.finish();
  print_tune(o, *m, rows);
  std::printf("\nWrote %s (from %s and %s; %s)\n", o.out.c_str(), m->speed_source.c_str(), tune_quality_path(o).c_str(),
              provenance.git_revision.c_str());
  if (o.speed.confirm > 0) confirm_tune(o, *m, choice, paper_index, provenance);
  return 0;
}

BoundCommand bind_tune(CLI::App& parent) {
  struct State {
    TuneOptions o;
    std::string tracer, render_tracer, res, shard = "0/1";
  };
  auto s = std::make_shared<State>();
  s->tracer = s->o.speed.tracer.text();
  s->render_tracer = s->o.error.tracer.text();
  s->res = fmt::format("{}x{}", s->o.width, s->o.height);
  TuneOptions& o = s->o;
  CLI::App* cmd = parent.add_subcommand("tune", "the fastest setting of ours within an error budget (one scene)");
  cmd->add_option("--scene", o.scene, "scene")->required();
  cmd->add_option("--generator", o.generator, "ours or contiguous")->capture_default_str();
  cmd->add_option("--tracer", s->tracer, "speed tracer (simt: modeled; cpu, embree, cuda: measured)")
      ->capture_default_str();
  cmd->add_option("--render-tracer", s->render_tracer, "tracer of the quality renders")->capture_default_str();
  cmd->add_option(
         "--render-device", o.error.device,
         "cpu, cuda or cuda:pipeline=fused: the quality renders on the device path tracer (as quality --device)")
      ->capture_default_str();
  cmd->add_option("--res", s->res, "resolution WxH")->capture_default_str();
  cmd->add_option("--budget", o.error.budget, "error ratios to noopt: ds8=R,rel=R,flip=R,bias=none|any")
      ->capture_default_str();
  cmd->add_option("--space", o.space, "axes tile=.. k=.. order=.. hybrid=.. frame=..")->capture_default_str();
  cmd->add_option("--search", o.search, "fastest (stop at the first setting within budget) or grid")
      ->capture_default_str();
  cmd->add_option("--rank", o.speed.rank, "e2e or trace: the speed that ranks settings")->capture_default_str();
  cmd->add_option("--frames", o.error.frames, "frames per render")->capture_default_str();
  cmd->add_option("--seeds", o.error.seeds, "renders per setting (seeds seed ..)")->capture_default_str();
  cmd->add_option("--ref-frames", o.error.ref_frames, "NoOpt frames of the reference")->capture_default_str();
  cmd->add_option("--speed-frames", o.speed.frames, "frames of the speed stage")->capture_default_str();
  cmd->add_option("--repeat", o.speed.repeats, "timed traces per batch (measured tracers; 0: 9 on a GPU, 7 on the CPU)")
      ->capture_default_str();
  cmd->add_option("--seed", o.seed, "random seed")->capture_default_str();
  cmd->add_option("--max-depth", o.error.max_depth, "scattering events per path")->capture_default_str();
  cmd->add_option("--rr-depth", o.error.rr_depth, "Russian roulette from this bounce on")->capture_default_str();
  cmd->add_option("--speed-csv", o.speed.csv,
                  "take the speeds from this table/sweep CSV (e.g. a tune's <stem>-speed.csv from a GPU machine)");
  cmd->add_option("--quality-csv", o.error.csv, "the error stage's CSV (default <out stem>-quality.csv; shareable)");
  cmd->add_option("--out", o.out, "CSV of the decision (stages: <stem>-speed.csv, <stem>-quality.csv)")
      ->capture_default_str();
  cmd->add_option("--cache", o.error.cache_dir, "reference cache folder (default $RAYCOH_CACHE or results/cache)");
  cmd->add_option("--images", o.error.image_dir, "folder for renders (default <stem>-quality-images)");
  cmd->add_option("--shard", s->shard, "I/N with --search grid: only shard I of both stages' units")
      ->capture_default_str();
  cmd->add_flag("--force", o.force, "measure afresh instead of resuming the stages' files");
  CLI::Option* confirm = cmd->add_option(
      "--confirm", o.speed.confirm, "N in [1, 64]: re-measure the speed call on N fresh seeds (<stem>-confirm.csv)");
  return {cmd, [s, confirm](const Provenance& provenance) {
            if (confirm->count() > 0 && (s->o.speed.confirm < 1 || s->o.speed.confirm > kMaxConfirmSeeds))
              throw Error(fmt::format("--confirm {}: must be in [1, {}] (fresh seeds to re-measure the speed call on)",
                                      s->o.speed.confirm, kMaxConfirmSeeds));
            s->o.speed.tracer = parse_plugin_spec(s->tracer);
            s->o.error.tracer = parse_plugin_spec(s->render_tracer);
            std::tie(s->o.width, s->o.height) = parse_res("--res", s->res);
            s->o.shard = parse_shard("--shard", s->shard);
            return run_tune(s->o, provenance);
          }};
}

}  // namespace raycoh
