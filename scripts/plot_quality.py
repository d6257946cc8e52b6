#!/usr/bin/python3
"""The PSNR table (the paper's Table 2) from `raycoh quality` CSV files: a grouped bar chart (with the standard
deviation over the independent renders as error bars) and, with --markdown, the table itself: one row per
generator, one column per scene.

usage: plot_quality.py quality.csv [more.csv ...] --out psnr.png [--markdown table.md|-]
                       [--metric psnr|ssim|rel_mse|rmse|bias2]
"""
import argparse
import math
import sys

import numpy as np

from plotlib import TRACER_COLUMNS, fail, footer, number, plt, read_csv, save


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("csv", nargs="+", help="CSV files written by raycoh quality")
    ap.add_argument("--out", help="figure file (.png, .pdf, .svg)")
    ap.add_argument("--markdown", help="write the table as markdown to this file ('-': standard output)")
    ap.add_argument("--metric", choices=["psnr", "ssim", "rel_mse", "rmse", "bias2"], default="psnr")
    a = ap.parse_args()
    if not a.out and not a.markdown:
        fail("nothing to do: give --out and/or --markdown")

    rows = read_csv(a.csv, ["scene", "method", "frames", "ref_frames", a.metric] + TRACER_COLUMNS)
    scenes, methods, cell, spread = [], [], {}, {}
    for r in rows:
        key = (r["method"], r["scene"])
        cell[key] = number(r, a.metric)
        spread[key] = number(r, "psnr_std") if a.metric == "psnr" and "psnr_std" in r else math.nan
        if r["scene"] not in scenes:
            scenes.append(r["scene"])
        if r["method"] not in methods:
            methods.append(r["method"])
    frames = sorted({r["frames"] for r in rows})
    ref_frames = sorted({r["ref_frames"] for r in rows if r["ref_frames"]})
    caption = (f"{a.metric.upper() if a.metric == 'psnr' else a.metric} after {'/'.join(frames)} frames against "
               f"{'/'.join(ref_frames) or 'given'}-frame references")

    if a.markdown:
        fmt = "{:.2f}" if a.metric == "psnr" else "{:.4g}"
        lines = [caption, "", "| generator | " + " | ".join(scenes) + " |", "|---|" + "---:|" * len(scenes)]
        for m in methods:
            vals = [cell.get((m, s), math.nan) for s in scenes]
            lines.append(f"| {m} | " + " | ".join("" if math.isnan(v) else fmt.format(v) for v in vals) + " |")
        text = "\n".join(lines) + "\n"
        if a.markdown == "-":
            sys.stdout.write(text)
        else:
            try:
                with open(a.markdown, "w") as f:
                    f.write(text)
            except OSError as e:
                fail(f"{a.markdown}: cannot write: {e}")
            print(f"wrote {a.markdown}")

    if a.out:
        fig, ax = plt.subplots(figsize=(max(5, 1.4 * len(scenes) * max(1, len(methods) / 2)), 3.8))
        x = np.arange(len(scenes))
        width = 0.8 / len(methods)
        for mi, m in enumerate(methods):
            vals = [cell.get((m, s), np.nan) for s in scenes]
            errs = [spread.get((m, s), np.nan) for s in scenes]
            bars = ax.bar(x + (mi - (len(methods) - 1) / 2) * width, vals, width, label=m,
                          yerr=None if all(np.isnan(errs)) else np.nan_to_num(errs), capsize=3)
            for b, v in zip(bars, vals):
                if np.isfinite(v):
                    ax.annotate(f"{v:.2f}" if a.metric == "psnr" else f"{v:.3g}",
                                (b.get_x() + b.get_width() / 2, v), ha="center", va="bottom", fontsize=7)
        ax.set_xticks(x, scenes)
        ax.set_ylabel(a.metric + (" (dB)" if a.metric == "psnr" else ""))
        ax.set_title(caption, fontsize=9)
        ax.legend(fontsize=8)
        fig.tight_layout()
        footer(fig, rows)
        save(fig, a.out)


if __name__ == "__main__":
    main()
