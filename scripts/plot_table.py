#!/usr/bin/python3
"""Speedup bars per scene and method (the paper's Table 1) from `raycoh table` CSV files.

For every scene, tracer and method the speed is sum(rays) / sum(time) over the frames of the secondary pass,
time = trace_ms (--speed trace, the default) or e2e_ms (--speed e2e: generation + reordering + trace), and the
bar is its ratio to the `noopt` method on the same scene and tracer (1 = no gain). One panel per tracer. For a
modelling tracer (simt) the ratio is of modeled cost per ray (its wall time is the model's), trace speed only.

usage: plot_table.py table.csv [more.csv ...] --out speedup.png [--speed trace|e2e] [--tracer NAME]
                     [--primary] [--title TEXT]
"""
import argparse
import textwrap
from collections import defaultdict

import numpy as np

from plotlib import cost_time, fail, is_modeled, number, plt, read_csv, save, tracer_label


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("csv", nargs="+", help="CSV files written by raycoh table")
    ap.add_argument("--out", required=True, help="figure file (.png, .pdf, .svg)")
    ap.add_argument("--speed", choices=["trace", "e2e"], default="trace",
                    help="trace-only speed (trace_ms) or end to end (e2e_ms)")
    ap.add_argument("--tracer", help="only this tracer (name, e.g. cpu or embree)")
    ap.add_argument("--primary", action="store_true", help="also show primary rays (the coherent bound)")
    ap.add_argument("--title", default=None)
    a = ap.parse_args()

    time_col = "trace_ms" if a.speed == "trace" else "e2e_ms"
    rows = read_csv(a.csv, ["scene", "pass", "method", "tracer", "rays", time_col])
    sums = defaultdict(lambda: [0.0, 0.0])  # (tracer, scene, method) -> [rays, ms]
    scenes, methods, tracers = [], [], []
    for r in rows:
        if a.tracer and r["tracer"] != a.tracer:
            continue
        if r["pass"] == "primary":
            if not a.primary:
                continue
            method, t = "primary", cost_time(r)
        else:
            method, t = r["method"], cost_time(r, time_col)
        if not (t > 0):
            continue
        key = (tracer_label(r) + (" (MODELED GPU time)" if is_modeled(r) else ""), r["scene"], method)
        sums[key][0] += number(r, "rays")
        sums[key][1] += t
        for lst, v in ((tracers, key[0]), (scenes, key[1]), (methods, key[2])):
            if v not in lst:
                lst.append(v)
    if not sums:
        fail("no rows with a positive time" + (f" for tracer {a.tracer}" if a.tracer else ""))
    if "noopt" not in methods:
        fail("no noopt rows: speedups are ratios to the noopt baseline (run raycoh table with noopt)")

    fig, axes = plt.subplots(len(tracers), 1, figsize=(max(6, 1.2 * len(scenes) * max(1, len(methods) / 3)),
                                                       3.6 * len(tracers)), squeeze=False)
    width = 0.8 / len(methods)
    for ax, tracer in zip(axes[:, 0], tracers):
        x = np.arange(len(scenes))
        for mi, method in enumerate(methods):
            values = []
            for scene in scenes:
                base, cur = sums.get((tracer, scene, "noopt")), sums.get((tracer, scene, method))
                ok = base and cur and base[1] > 0 and cur[1] > 0
                values.append((cur[0] / cur[1]) / (base[0] / base[1]) if ok else np.nan)
            bars = ax.bar(x + (mi - (len(methods) - 1) / 2) * width, values, width, label=method)
            for b, v in zip(bars, values):
                if np.isfinite(v):
                    ax.annotate(f"{v:.2f}", (b.get_x() + b.get_width() / 2, v), ha="center", va="bottom",
                                fontsize=7)
        ax.axhline(1.0, color="black", linewidth=0.8)
        ax.set_xticks(x, scenes)
        ax.set_ylabel(f"speedup over noopt ({a.speed})")
        ax.set_title(textwrap.fill(f"tracer {tracer}", 120), fontsize=9)
        ax.legend(fontsize=8, ncol=min(4, len(methods)))
    if a.title:
        fig.suptitle(a.title)
    fig.tight_layout()
    save(fig, a.out)


if __name__ == "__main__":
    main()
