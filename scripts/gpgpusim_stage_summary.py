#!/usr/bin/env python3
"""The two tables of results/model/stage-counters/gpgpusim/README.md that combine several runs (SIMULATED) with the
stage model's prediction (MODELED): "The kernels beside the model" and the issue breakdown, printed as markdown from
the committed run folders (runs/NAME/gpgpusim.log.xz) and prediction CSVs, by scripts/gpgpusim_stage_stats.py's
reading of the logs (the timed launch, n = 2, of noopt_kernel and group_kernel).

Usage: scripts/gpgpusim_stage_summary.py DIR > DIR/beside-model.md   (DIR: results/model/stage-counters/gpgpusim)

Columns: resident warps (CTA/core x 2 warps, and the achieved mean over the blocks' span); PTX instructions per warp
(gpgpu_n_tot_w_icount / warps); the model's cycles_per_warp, resident_warps ("(32)" where the simulator was limited
to one block per SM: the model's figure is the unlimited one) and chain_cycles; block lifetime mean, median, max;
cycles per issued instruction of a warp (mean lifetime / instructions per warp); the scheduler's issue breakdown in
% of 4 x span; memory stage stalled = gpgpu_n_stall_shd_mem / span. Ratios are MODELED / SIMULATED.
Standard library only.
"""
import csv
import os
import sys

from gpgpusim_stage_stats import fmt, launches, lifetimes, pct, read_log

# run folder, scene in the prediction, prediction CSV, label in the first table, label in the issue table
RUNS = (("cornell-64x64", "cornell", "prediction.csv", "cornell", "cornell 64×64"),
        ("sibenik-64x64", "sibenik", "prediction.csv", "sibenik", "sibenik 64×64"),
        ("cornell-64x64-cta1", "cornell", "prediction.csv", "cornell 64×64, one block per SM",
         "cornell 64×64, one block"),
        ("cornell-32x32-cta1", "cornell", "prediction-32x32.csv", "cornell 32×32, one block per SM",
         "cornell 32×32, one block"),
        ("sibenik-32x32-cta1", "sibenik", "prediction-32x32.csv", "sibenik 32×32, one block per SM",
         "sibenik 32×32, one block"))
KERNELS = (("noopt_kernel", "noopt"), ("group_kernel", "ours"))


def timed(folder):
    """kernel -> its timed launch's statistics block (n = 2)."""
    blocks = read_log(os.path.join(folder, "gpgpusim.log.xz"))
    return {s: b for n, s, b in launches(blocks, [k for k, _ in KERNELS]) if n == 2}


def modeled(path, scene, method):
    with open(path, newline="") as f:
        return next(r for r in csv.DictReader(f) if r["kernel"] == "gen" and r["scene"] == scene
                    and r["method"] == method)


def main(argv):
    if len(argv) != 1:
        sys.exit(__doc__.split("\n\n")[1])
    folder = argv[0]
    runs = [(r, timed(os.path.join(folder, "runs", r[0]))) for r in RUNS]
    print("| scene | kernel | resident warps / SM, SIMULATED (theoretical, achieved) | MODELED | PTX instructions / "
          "warp, SIMULATED | partition cycles / warp, MODELED (SASS sm_86 path) | ratio | block lifetime, SIMULATED "
          "| median, max | chain, MODELED | ratio | cycles per issued instruction of a warp, SIMULATED |")
    print("|---|---|---|---:|---:|---:|---:|---:|---|---:|---:|---:|")
    for (name, scene, prediction, label, _), found in runs:
        for kernel, method in KERNELS:
            b, m = found[kernel], modeled(os.path.join(folder, prediction), scene, method)
            mean, median, longest, _, achieved = lifetimes(b)
            per_warp, cta = b["gpgpu_n_tot_w_icount"] / b["warps"], b["limit"][0]
            cw, chain, resident = float(m["cycles_per_warp"]), float(m["chain_cycles"]), float(m["resident_warps"])
            shown = fmt(resident) if cta * b["warps_per_block"] >= resident else f"({fmt(resident)})"
            print(f"| {label} | {kernel} | {cta * b['warps_per_block']}, {fmt(achieved, 1)} | {shown} | "
                  f"{fmt(per_warp)} | {fmt(cw)} | {cw / per_warp:.2f} | {fmt(mean)} | {fmt(median)}, {fmt(longest)} | "
                  f"{fmt(chain)} | **{chain / mean:.2f}** | {mean / per_warp:.1f} |")
    print()
    print("| pass | kernel | issued % | W0_Scoreboard % (no warp ready: all wait on a register) | W0_Idle % (no valid "
          "instruction: barrier, empty buffer, no warp) | Stall % (a warp ready, its unit or the memory stage full) | "
          "memory stage stalled, % of cycles | L1D accesses / misses / reservation fails |")
    print("|---|---|---:|---:|---:|---:|---:|---|")
    for (name, scene, prediction, _, label), found in runs:
        for kernel, _ in KERNELS:
            b = found[kernel]
            total = b["issued"] + b["W0_Scoreboard"] + b["W0_Idle"] + b["Stall"]
            span = lifetimes(b)[3]
            stall = pct(b["Stall"], total)
            stall = stall if b["limit"][0] == 1 else f"**{stall}**"
            print(f"| {label} | {kernel} | {pct(b['issued'], total)} | {pct(b['W0_Scoreboard'], total)} | "
                  f"{pct(b['W0_Idle'], total)} | {stall} | {100 * b['gpgpu_n_stall_shd_mem'] / span:.0f} | "
                  + " / ".join(fmt(b[f"L1D_total_cache_{k}"]) for k in ("accesses", "misses", "reservation_fails"))
                  + " |")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
