#!/usr/bin/python3
"""Error against time curves from a `raycoh converge` CSV: one line per generator, one panel per scene.

x is the cumulative wall-clock time of the frames (--clock wall_s, the default) or the cumulative trace time
(--clock trace_s); y is the error of the running mean against the reference (--metric rel_mse by default; mse,
rmse on log axes; psnr, ssim on a linear axis). With <csv stem>-summary.csv beside it, the equal-time error
ratio and equal-error speedup are written into the legend.

usage: plot_converge.py converge.csv --out curves.png [--metric rel_mse|mse|rmse|psnr|ssim]
                        [--clock wall_s|trace_s]
"""
import argparse
import csv
import os
from collections import defaultdict

from plotlib import fail, footer, number, plt, read_csv, save


def summary_notes(path, clock):
    """method -> legend note from the summary CSV of the same run (if present)."""
    notes = {}
    summary = os.path.splitext(path)[0] + "-summary.csv"
    if not os.path.isfile(summary):
        return notes
    with open(summary, newline="") as f:
        for r in csv.DictReader(f):
            if r.get("clock") == clock.replace("_s", ""):
                try:
                    notes[r["method"]] = (f"error x{float(r['equal_time_error_ratio']):.2f} at equal time, "
                                          f"{float(r['equal_error_speedup']):.2f}x at equal error")
                except (KeyError, ValueError):
                    pass
    return notes


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("csv", help="CSV written by raycoh converge")
    ap.add_argument("--out", required=True, help="figure file (.png, .pdf, .svg)")
    ap.add_argument("--metric", choices=["rel_mse", "mse", "rmse", "psnr", "ssim"], default="rel_mse")
    ap.add_argument("--clock", choices=["wall_s", "trace_s"], default="wall_s")
    a = ap.parse_args()

    rows = read_csv(a.csv, ["scene", "method", "frame", a.clock, a.metric])
    curves = defaultdict(list)
    scenes = []
    for r in rows:
        t, e = number(r, a.clock), number(r, a.metric)
        if t > 0 and e == e:
            curves[(r["scene"], r["method"])].append((t, e))
            if r["scene"] not in scenes:
                scenes.append(r["scene"])
    if not curves:
        fail(f"no rows with a positive {a.clock} and a {a.metric} value")
    notes = summary_notes(a.csv, a.clock)
    log = a.metric in ("rel_mse", "mse", "rmse")
    fig, axes = plt.subplots(1, len(scenes), figsize=(6 * len(scenes), 4.2), squeeze=False)
    for ax, scene in zip(axes[0], scenes):
        for (s, method), pts in curves.items():
            if s != scene:
                continue
            pts.sort()
            label = method + (f" ({notes[method]})" if method in notes else "")
            ax.plot([p[0] for p in pts], [p[1] for p in pts], label=label, linewidth=1.2)
        ax.set_xscale("log")
        if log:
            ax.set_yscale("log")
        ax.set_xlabel("wall-clock time of the frames (s)" if a.clock == "wall_s" else "trace time (s)")
        ax.set_ylabel(a.metric)
        ax.set_title(scene)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    fig.tight_layout()
    footer(fig, rows)
    save(fig, a.out)


if __name__ == "__main__":
    main()
