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
from collections import defaultdict

import numpy as np

from plotlib import (OKABE_ITO, TRACER_COLUMNS, cost_time, fail, footer, is_modeled, lighten, number, plt, read_csv, save,
                     tracer_label)


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
    rows = read_csv(a.csv, ["scene", "pass", "method", "tracer", "rays", time_col] + TRACER_COLUMNS)
    sums = defaultdict(lambda: [0.0, 0.0])  # (tracer, scene, method) -> [rays, ms]
    scenes, methods, tracers = [], [], []
    method_parts, used_rows = {}, []  # method -> (generator, encoder); the rows plotted (for the footer)
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
        key = (tracer_label(r) + (" — MODELED GPU time" if is_modeled(r) else " — measured"), r["scene"], method)
        method_parts[method] = ("primary", "none") if method == "primary" else (
            r.get("generator") or method.split("+")[0], r.get("encoder") or "none")
        used_rows.append(r)
        sums[key][0] += number(r, "rays")
        sums[key][1] += t
        for lst, v in ((tracers, key[0]), (scenes, key[1]), (methods, key[2])):
            if v not in lst:
                lst.append(v)
    if not sums:
        fail("no rows with a positive time" + (f" for tracer {a.tracer}" if a.tracer else ""))
    if "noopt" not in methods:
        fail("no noopt rows: speedups are ratios to the noopt baseline (run raycoh table with noopt)")

    # Methods grouped by generator (one hue each, a gap between groups), encoders as shades of the hue.
    generators, encoders = [], []
    for m in methods:
        g, e = method_parts[m]
        generators += [g] if g not in generators else []
        encoders += [e] if e not in encoders else []
    order = [m for g in generators for e in encoders for m in methods if method_parts[m] == (g, e)]
    hues, hue_of = iter(OKABE_ITO * 2), {}
    for g in generators:
        hue_of[g] = "#000000" if g == "primary" else "#666666" if g == "noopt" else next(hues)

    def colour(m):
        g, e = method_parts[m]
        return lighten(hue_of[g], 0.75 * encoders.index(e) / max(len(encoders), 2))

    positions, x, prev = {}, 0.0, None
    for m in order:
        g = method_parts[m][0]
        x += 0.6 if prev is not None and g != prev else 0.0
        positions[m], prev, x = x, g, x + 1.0
    span = x + 2.0  # one scene's bars and the gap to the next

    fig, axes = plt.subplots(len(tracers), 1, figsize=(max(7, 0.16 * span * len(scenes) + 2), 3.8 * len(tracers)),
                             squeeze=False)
    for ax, tracer in zip(axes[:, 0], tracers):
        for si, scene in enumerate(scenes):
            base = sums.get((tracer, scene, "noopt"))
            for m in order:
                cur = sums.get((tracer, scene, m))
                ok = base and cur and base[1] > 0 and cur[1] > 0
                v = (cur[0] / cur[1]) / (base[0] / base[1]) if ok else np.nan
                bx = si * span + positions[m]
                ax.bar(bx, v, 0.9, color=colour(m), edgecolor="#333333", linewidth=0.4)
                if np.isfinite(v) and len(order) <= 10:
                    ax.annotate(f"{v:.2f}", (bx, v), ha="center", va="bottom", fontsize=7)
        ax.axhline(1.0, color="black", linewidth=0.8, linestyle="--")
        ax.set_ylim(bottom=0)
        ax.set_xticks([si * span + (span - 2.0) / 2 - 0.5 for si in range(len(scenes))], scenes)
        ax.set_ylabel(f"speed-up over noopt\n({a.speed}; axis from 0)")
        ax.set_title(tracer, fontsize=10)
    from matplotlib.patches import Patch
    gen_handles = [Patch(color=hue_of[g], label=g) for g in generators]
    enc_handles = [Patch(facecolor=lighten("#444444", 0.75 * i / max(len(encoders), 2)), edgecolor="#333333",
                         label=e) for i, e in enumerate(encoders)]
    top = axes[0, 0]
    leg = top.legend(handles=gen_handles, title="colour = generator", fontsize=8, title_fontsize=8,
                     loc="upper left", bbox_to_anchor=(1.01, 1.0))
    top.add_artist(leg)
    if len(encoders) > 1:
        top.legend(handles=enc_handles, title="shade = encoder", fontsize=8, title_fontsize=8, loc="upper left",
                   bbox_to_anchor=(1.01, 0.45))
    footer(fig, used_rows)
    if a.title:
        fig.suptitle(a.title)
    fig.tight_layout()
    save(fig, a.out)


if __name__ == "__main__":
    main()
