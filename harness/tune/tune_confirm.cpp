// `raycoh tune --confirm N`; see harness/tune/tune_confirm.h.
#include "harness/tune/tune_confirm.h"

#include <fmt/format.h>

#include <cstdio>

#include "harness/image/render_common.h"
#include "harness/tune/tune_speed.h"
#include "records/record_csv.h"
#include "records/tune_row.h"

namespace raycoh {

namespace {

// What a ratio allows one to say: its interval's verdict, or without one (a model's run) the point's side of 1.
std::string call_of(const SpeedRatio& r) {
  if (r.has_interval) return speed_verdict(r);
  return r.ratio > 1 ? "faster" : r.ratio < 1 ? "slower" : "indistinguishable";
}

std::string held_of(const std::string& claim, const std::string& seen) {
  if (claim == "indistinguishable") return seen == "indistinguishable" ? "held" : "not held";
  if (seen == claim) return "held";
  return seen == "indistinguishable" ? "indistinguishable" : "not held";
}

double nan_unless(bool has, double v) { return has ? v : std::nan(""); }

// The call confirmed: the fastest passing setting against the paper's default, else the paper's against noopt.
struct Call {
  const TuneCandidate* subject = nullptr;
  std::string baseline;        // a setting's spec, or "noopt"
  std::string baseline_words;  // "the paper's default", "noopt"
  SpeedRatio search;
  std::string claim;
};

Call call_to_confirm(const TuneOptions& o, const TuneMeasured& m, const TuneChoice& ch, int paper) {
  Call c;
  const bool vs_paper = ch.fastest_passing >= 0 && ch.fastest_passing != paper;
  c.subject = &m.candidates[static_cast<size_t>(vs_paper ? ch.fastest_passing : paper)];
  c.baseline = vs_paper ? paper_setting(o.generator).spec() : "noopt";
  c.baseline_words = vs_paper ? "the paper's default" : "noopt";
  c.search = vs_paper ? c.subject->to_paper : c.subject->to_noopt;
  c.claim = call_of(c.search);
  return c;
}

TuneConfirmRow confirm_row(const TuneOptions& o, const Call& call, const TuneSpeeds& sp, const Provenance& p) {
  const TuneSpeed &base = sp.by_method.at(call.baseline), &subject = sp.by_method.at(call.subject->setting.spec()),
                  &noopt = sp.by_method.at("noopt");
  const SpeedRatio r = tune_speed_ratio(base, subject), up = tune_speed_ratio(noopt, subject);
  TuneConfirmRow row;
  row.scene_spec = o.scene;
  row.scene = sp.scene;
  row.setting = call.subject->setting.spec();
  row.baseline = call.baseline;
  row.claim = call.claim;
  row.search_ratio = call.search.ratio;
  std::tie(row.ratio, row.lo, row.hi) =
      std::make_tuple(r.ratio, nan_unless(r.has_interval, r.lo), nan_unless(r.has_interval, r.hi));
  row.verdict = speed_verdict(r);
  row.held = held_of(call.claim, call_of(r));
  std::tie(row.setting_speedup, row.setting_speedup_lo, row.setting_speedup_hi) =
      std::make_tuple(up.ratio, nan_unless(up.has_interval, up.lo), nan_unless(up.has_interval, up.hi));
  row.setting_mray_s = subject.ranked;
  row.baseline_mray_s = base.ranked;
  row.noopt_mray_s = noopt.ranked;
  row.tracer_spec = sp.tracer_label;
  row.speed_kind = sp.modeled ? "modeled" : "measured";
  row.rank = o.speed.rank;
  row.speed_csv = sp.source;
  row.width = o.width, row.height = o.height, row.speed_frames = o.speed.frames, row.repeats = sp.repeats;
  row.waves = sp.wave_rays > 0 ? subject.rays_per_frame / sp.wave_rays : std::nan("");
  row.provenance = p;
  return row;
}

std::string ratio_words(double ratio, double lo, double hi) {
  return std::isnan(lo) ? fmt::format("{:.2f}x", ratio) : fmt::format("{:.2f}x [{:.2f}, {:.2f}]", ratio, lo, hi);
}

void print_closing(const Call& call, const std::vector<TuneConfirmRow>& rows, const TuneConfirmRow& pooled) {
  int held = 0, not_held = 0, unclear = 0;
  for (const TuneConfirmRow& r : rows) ++(r.held == "held" ? held : r.held == "not held" ? not_held : unclear);
  const char* words = not_held > 0  ? "did not hold"
                      : unclear > 0 ? "is not confirmed (indistinguishable at some seeds)"
                                    : "held at every seed";
  std::printf(
      "Confirm: %s %s %s (search: %s) held at %d of %zu fresh seeds, not held at %d, indistinguishable at %d; "
      "pooled over their frames %s (%s): the call %s.\n",
      call.subject->setting.spec().c_str(), call.claim.c_str(),
      call.claim == "indistinguishable" ? ("from " + call.baseline_words).c_str()
                                        : ("than " + call.baseline_words).c_str(),
      ratio_text(call.search).c_str(), held, rows.size(), not_held, unclear,
      ratio_words(pooled.ratio, pooled.lo, pooled.hi).c_str(), pooled.verdict.c_str(), words);
}

}  // namespace

std::string tune_confirm_path(const TuneOptions& o) { return stem_path(o.out) + "-confirm.csv"; }

void confirm_tune(const TuneOptions& o, const TuneMeasured& m, const TuneChoice& ch, int paper,
                  const Provenance& provenance) {
  const Call call = call_to_confirm(o, m, ch, paper);
  std::vector<std::string> methods{paper_setting(o.generator).spec()};
  if (call.subject->setting.spec() != methods.front()) methods.push_back(call.subject->setting.spec());
  const uint32_t first = o.seed + static_cast<uint32_t>(o.error.seeds);
  std::printf(
      "\nConfirm: %s %s %s at %d fresh seed(s) from %u (the search's speed seed was %u, its renders' %u..%u), "
      "%d frame(s) each:\n",
      call.subject->setting.spec().c_str(), call.claim == "indistinguishable" ? "vs" : "over",
      call.baseline_words.c_str(), o.speed.confirm, first, o.seed, o.seed,
      o.seed + static_cast<uint32_t>(o.error.seeds) - 1, o.speed.frames);
  std::vector<TuneConfirmRow> rows;
  TuneSpeeds pooled;
  for (int i = 0; i < o.speed.confirm; ++i) {
    const uint32_t seed = first + static_cast<uint32_t>(i);
    const std::string path = fmt::format("{}-confirm-seed{}-speed.csv", stem_path(o.out), seed);
    const TuneSpeeds sp = measure_tune_speeds(o, methods, seed, path, provenance);
    TuneConfirmRow row = confirm_row(o, call, sp, provenance);
    row.kind = "seed";
    row.seeds = std::to_string(seed);
    std::printf("  seed %u: %s %s (%s): %s\n", seed, ratio_words(row.ratio, row.lo, row.hi).c_str(),
                call.baseline_words.c_str(), row.verdict.c_str(), row.held.c_str());
    rows.push_back(row);
    if (i == 0) {
      pooled = sp;
      for (auto& [method, s] : pooled.by_method) s.times.clear();
    }
    for (const auto& [method, s] : sp.by_method)  // every seed's frames side by side, keyed apart
      for (const auto& [frame, t] : s.times) pooled.by_method[method].times[i * 1000000 + frame] = t;
  }
  TuneConfirmRow all = confirm_row(o, call, pooled, provenance);
  all.kind = "pooled";
  for (const TuneConfirmRow& r : rows) all.seeds += (all.seeds.empty() ? "" : ";") + r.seeds;
  all.setting_mray_s = all.baseline_mray_s = all.noopt_mray_s = std::nan("");
  print_closing(call, rows, all);
  RecordCsv<TuneConfirmRow> csv(tune_confirm_path(o), tune_confirm_schema(), CsvWriter::Options::once(true));
  for (const TuneConfirmRow& r : rows) csv.write(r);
  csv.write(all);
  csv.finish();
  std::printf("Wrote %s\n", tune_confirm_path(o).c_str());
}

}  // namespace raycoh
