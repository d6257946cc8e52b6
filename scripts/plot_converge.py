#!/usr/bin/python3
"""Error against time curves from `raycoh converge` CSVs (one or more, e.g. one per scene): one line per generator,
one row of panels per scene, one panel per clock.

Clocks (--clock, comma-separated): wall_s, the cumulative wall-clock time of the frames on the CPU; trace_s, the
cumulative time of the CPU tracer calls; modeled_gpu_s, the cumulative MODELED time of the same frames on the
`simt` tracer's GPU (`converge --gpu-model`; never added to a measured time). The default is wall_s and, when
the CSV has modeled times, modeled_gpu_s beside it. y is the error of the running mean against the reference
(--metric rel_mse by default; mse, rmse on log axes; psnr, ssim on a linear axis). With <csv stem>-summary.csv
beside it, the equal-time error ratio and equal-error speedup of each clock are written into its legend.

usage: plot_converge.py converge.csv [more.csv ...] --out curves.png [--metric rel_mse|mse|rmse|psnr|ssim]
                        [--clock wall_s|trace_s|modeled_gpu_s[,...]]
"""
import argparse
import csv
import os
from collections import defaultdict

from plotlib import TRACER_COLUMNS, fail, footer, number, plt, read_csv, save
from result_key import result_label

CLOCKS = {
    "wall_s": "CPU wall-clock time of the frames (s), measured",
    "trace_s": "CPU trace time (s), measured",
    "modeled_gpu_s": "GPU time (s), MODELED",
}


def short_model(row):
    """'simt[preset=rtx3060]' from the typed gpu_preset column (gpu_model keeps every parameter); '' without one."""
    return result_label("simt", preset=row["gpu_preset"]) if row.get("gpu_preset") else row.get("gpu_model", "")


def summary_notes(path, clock):
    """(scene, method) -> legend note from the summary CSV of the same run (if present)."""
    notes = {}
    summary = os.path.splitext(path)[0] + "-summary.csv"
    if not os.path.isfile(summary):
        return notes
    with open(summary, newline="") as f:
        for r in csv.DictReader(f):
            if r.get("clock") == clock[:-2]:
                try:
                    notes[(r.get("scene"), r["method"])] = (
                        f"error x{float(r['equal_time_error_ratio']):.2f} at equal time, "
                        f"{float(r['equal_error_speedup']):.2f}x at equal error")
                except (KeyError, ValueError):
                    pass
    return notes


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("csv", nargs="+", help="CSVs written by raycoh converge")
    ap.add_argument("--out", required=True, help="figure file (.png, .pdf, .svg)")
    ap.add_argument("--metric", choices=["rel_mse", "mse", "rmse", "psnr", "ssim"], default="rel_mse")
    ap.add_argument("--clock", default=None,
                    help="comma-separated clocks: wall_s, trace_s, modeled_gpu_s (default wall_s and, when "
                         "present, modeled_gpu_s)")
    a = ap.parse_args()

    rows = read_csv(a.csv, ["scene", "method", "frame", a.metric, "gpu_preset"] + TRACER_COLUMNS)
    if a.clock is None:
        has_model = any(r.get("modeled_gpu_s") not in (None, "") for r in rows)
        clocks = ["wall_s", "modeled_gpu_s"] if has_model else ["wall_s"]
    else:
        clocks = [c.strip() for c in a.clock.split(",") if c.strip()]
        for c in clocks:
            if c not in CLOCKS:
                fail(f"--clock {c}: expected one of {', '.join(CLOCKS)}")
        if not clocks:
            fail("--clock: empty list")
    read_csv(a.csv, clocks)  # every clock asked for must be a column
    scenes = []
    for r in rows:
        if r["scene"] not in scenes:
            scenes.append(r["scene"])
    log = a.metric in ("rel_mse", "mse", "rmse")
    fig, axes = plt.subplots(len(scenes), len(clocks), figsize=(6 * len(clocks), 4.2 * len(scenes)), squeeze=False)
    for ci, clock in enumerate(clocks):
        curves = defaultdict(list)
        for r in rows:
            t, e = number(r, clock), number(r, a.metric)
            if t > 0 and e == e:
                curves[(r["scene"], r["method"])].append((t, e))
        if not curves:
            fail(f"no rows with a positive {clock} and a {a.metric} value")
        notes = {}
        for path in a.csv:
            notes.update(summary_notes(path, clock))
        for si, scene in enumerate(scenes):
            ax = axes[si][ci]
            for (s, method), pts in curves.items():
                if s != scene:
                    continue
                pts.sort()
                label = method + (f" ({notes[(s, method)]})" if (s, method) in notes else "")
                ax.plot([p[0] for p in pts], [p[1] for p in pts], label=label, linewidth=1.2)
            ax.set_xscale("log")
            if log:
                ax.set_yscale("log")
            ax.set_xlabel(CLOCKS[clock])
            ax.set_ylabel(a.metric)
            title = scene + (" — MODELED GPU clock" if clock == "modeled_gpu_s" else "")
            if clock == "modeled_gpu_s":
                models = sorted({short_model(r) for r in rows if r["scene"] == scene} - {""})
                if models:
                    title += f"\n{', '.join(models)}"
            ax.set_title(title, fontsize=10)
            ax.grid(True, which="both", alpha=0.3)
            if ax.lines:
                ax.legend(fontsize=8)
    fig.tight_layout()
    footer(fig, rows)
    save(fig, a.out)


if __name__ == "__main__":
    main()
