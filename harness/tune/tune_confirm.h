// `raycoh tune --confirm N`: after the search, the speed call is measured again on N fresh seeds (seed + seeds ..
// seed + seeds + N - 1: none of them the speed stage's seed or an error-stage render's), each a speed run of noopt,
// the paper's default and the fastest setting within the budget with the search's --speed-frames and --repeat
// (<out stem>-confirm-seed<S>-speed.csv, resumable). The call confirmed is the fastest passing setting's against
// the paper's default (harness/tune/tune_select.h settle_speed); when that is the paper's default itself (or nothing
// passes), the paper's default against noopt. Per seed: the ratio with its paired interval and whether the call
// held ("held": the seed's interval says the same; "not held": it excludes 1 on the other side, or, for a call of
// indistinguishable, excludes 1 at all; "indistinguishable": it holds 1), then a closing line over every seed and
// the pooled ratio over all seeds' frames. A modelling tracer's runs have no interval: its call and each seed's are
// the point ratio's side of 1. Rows: <out stem>-confirm.csv (records/tune_row.h TuneConfirmRow).
#pragma once

#include <string>
#include <vector>

#include "harness/tune/tune_run.h"
#include "harness/tune/tune_select.h"

namespace raycoh {

// The valid range of --confirm.
inline constexpr int kMaxConfirmSeeds = 64;

// <out stem>-confirm.csv.
std::string tune_confirm_path(const TuneOptions& o);

// Measures, prints and writes the confirmation (above); `paper`: the paper's default's index in m.candidates.
void confirm_tune(const TuneOptions& o, const TuneMeasured& m, const TuneChoice& choice, int paper,
                  const Provenance& provenance);

}  // namespace raycoh
