#!/usr/bin/python3
"""Markdown table of several `raycoh validate` runs side by side (what-if variants of the GPU timing model):
per run, the model's parameters that differ from the first run's, the batch order, the modeled NoOpt MRay/s and
its limiter, the modeled ratio of every Table 1 method, how many of the 22 ratio cells lie within +-15% of the
paper's, the mean and largest ratio error, and the saturation K = 32 -> 64 at tile (8,8). The paper's measured
figures are the first line. Every other figure is MODELED.

Usage: validate_summary.py validate.csv [validate.csv ...] [--labels a,b,...] [--out summary.md]
"""
import argparse
import os

from plotlib import fail, number, read_csv
from result_key import tracer_parameters

REQUIRED = ["table", "row", "paper_row", "tile", "k", "paper_mray_s", "paper_ratio", "modeled_mray_s",
            "modeled_ratio", "ratio_error", "modeled_limiter", "tracer_params", "order"]


def cells(rows, table):
    return [r for r in rows if r["table"] == table]


def k_cell(rows, tile, k):
    for r in cells(rows, "table3"):
        if r["tile"] == tile and int(number(r, "k")) == k:
            return r
    return None


def saturation(rows, column):
    k32, k64 = k_cell(rows, "8x8", 32), k_cell(rows, "8x8", 64)
    if k32 is None or k64 is None:
        return float("nan")
    return number(k64, column) / number(k32, column) - 1.0


def model_params(rows):
    """The simt parameters of a run, from `simt[preset=...,l1_tags=4,...]`."""
    return tracer_parameters(rows[0])


def summary_line(label, rows, base_params, methods):
    params = model_params(rows)
    changed = [f"{k}={v}" for k, v in params.items() if base_params.get(k) != v]
    errors = [abs(number(r, "ratio_error")) for r in cells(rows, "table1") + cells(rows, "table3")
              if r["paper_ratio"] not in ("", "nan") and r["paper_row"] != "NoOpt"]
    if not errors:
        fail(f"{label}: no Table 1 or Table 3 cells with a paper ratio")
    noopt = next(r for r in cells(rows, "table1") if r["paper_row"] == "NoOpt")
    by_paper = {r["paper_row"]: r for r in cells(rows, "table1")}
    ratios = [f"{number(by_paper[m], 'modeled_ratio'):.2f}" if m in by_paper else "-" for m in methods]
    within = sum(e <= 0.15 for e in errors)
    return (f"| {label} | {' '.join(changed) or '(as first)'} | {rows[0]['order']} | "
            f"{number(noopt, 'modeled_mray_s'):.1f} | {noopt['modeled_limiter']} | " + " | ".join(ratios) +
            f" | {within}/{len(errors)} | {100 * sum(errors) / len(errors):.0f}% | {100 * max(errors):.0f}% | "
            f"{100 * saturation(rows, 'modeled_ratio'):+.1f}% |")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("csv", nargs="+")
    ap.add_argument("--labels", help="comma-separated run labels (default: the file names)")
    ap.add_argument("--out", help="write the Markdown here instead of stdout")
    a = ap.parse_args()
    labels = a.labels.split(",") if a.labels else [os.path.splitext(os.path.basename(p))[0] for p in a.csv]
    if len(labels) != len(a.csv):
        fail(f"--labels has {len(labels)} names for {len(a.csv)} CSV files")
    runs = [read_csv(p, REQUIRED) for p in a.csv]
    for path, rows in zip(a.csv, runs):
        if not cells(rows, "table1") or not any(r["paper_row"] == "NoOpt" for r in rows):
            fail(f"{path}: needs table1 rows with the NoOpt baseline")
    first = runs[0]
    base_params = model_params(first)
    methods = [r["paper_row"] for r in cells(first, "table1") if r["paper_row"] != "NoOpt"]
    head = ("| run | parameters | order | NoOpt MRay/s | limiter | " + " | ".join(methods) +
            " | cells within +-15% | mean error | largest error | K 32 -> 64 at (8,8) |")
    rule = "|---|---|---|---:|---|" + "---:|" * len(methods) + "---:|---:|---:|---:|"
    by_paper = {r["paper_row"]: r for r in cells(first, "table1")}
    paper_noopt = number(by_paper["NoOpt"], "paper_mray_s")
    paper = (f"| paper (RTX 3060, measured) | | | {paper_noopt:.1f} | | " +
             " | ".join(f"{number(by_paper[m], 'paper_ratio'):.2f}" for m in methods) +
             f" | | | | {100 * saturation(first, 'paper_ratio'):+.1f}% |")
    lines = [f"First run's model: `{first[0]['tracer_params']}`. Ratios are to NoOpt; every figure but the "
             "paper's is MODELED.", "", head, rule, paper]
    lines += [summary_line(label, rows, base_params, methods) for label, rows in zip(labels, runs)]
    text = "\n".join(lines) + "\n"
    if a.out:
        with open(a.out, "w") as f:
            f.write(text)
    else:
        print(text, end="")


if __name__ == "__main__":
    main()
