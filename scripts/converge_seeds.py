#!/usr/bin/env python3
"""Summarise `raycoh converge` runs of several seeds: per scene, method and clock, the mean and standard error of
the equal-time error ratio and the equal-error speedup over the seeds' -summary.csv files, and how many seeds put
the method ahead of its baseline. One run's ratio spreads more than the methods' frame times differ (a firefly
copied across a reuse group moves it by several percent), so a claim about a ratio needs several seeds.

Usage: converge_seeds.py SUMMARY.csv... [--md OUT.md]
Prints a Markdown table; with --md also writes it. Bad input: one line naming the file and the problem, exit 2.
"""
import argparse
import csv
import math
import sys

NEEDED = ("scene", "method", "baseline", "clock", "equal_time_error_ratio", "equal_error_speedup")


def fail(msg):
    print(f"converge_seeds.py: {msg}", file=sys.stderr)
    sys.exit(2)


def mean_se(xs):
    m = sum(xs) / len(xs)
    if len(xs) < 2:
        return m, float("nan")
    var = sum((x - m) ** 2 for x in xs) / (len(xs) - 1)
    return m, math.sqrt(var / len(xs))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("summaries", nargs="+", help="-summary.csv files of raycoh converge, one per seed")
    ap.add_argument("--md", help="also write the table to this Markdown file")
    a = ap.parse_args()
    groups = {}
    for path in a.summaries:
        try:
            with open(path, newline="") as f:
                rows = list(csv.DictReader(f))
        except OSError as e:
            fail(f"cannot read {path}: {e.strerror}")
        if not rows:
            fail(f"{path}: no rows (expected a -summary.csv of raycoh converge)")
        missing = [c for c in NEEDED if c not in rows[0]]
        if missing:
            fail(f"{path}: missing column(s) {', '.join(missing)} (expected a -summary.csv of raycoh converge)")
        for r in rows:
            key = (r["scene"], r["method"], r["baseline"], r["clock"])
            try:
                t, s = float(r["equal_time_error_ratio"]), float(r["equal_error_speedup"])
            except ValueError:
                fail(f"{path}: non-numeric ratio in row {key}")
            groups.setdefault(key, []).append((t, s, path))
    lines = [
        "| scene | method vs baseline | clock | seeds | equal-time error ratio (mean ± s.e.) | below 1 | "
        "equal-error speedup (mean ± s.e.) |",
        "|---|---|---|---:|---:|---:|---:|",
    ]
    for (scene, method, base, clock), vals in sorted(groups.items()):
        t_m, t_se = mean_se([v[0] for v in vals])
        s_m, s_se = mean_se([v[1] for v in vals])
        below = sum(1 for v in vals if v[0] < 1)
        label = f"{clock} (MODELED)" if clock.startswith("modeled") else clock
        lines.append(
            f"| {scene} | {method} vs {base} | {label} | {len(vals)} | {t_m:.3f} ± {t_se:.3f} | {below}/{len(vals)} | "
            f"{s_m:.3f} ± {s_se:.3f} |"
        )
    text = "\n".join(lines) + "\n"
    sys.stdout.write(text)
    if a.md:
        with open(a.md, "w") as f:
            f.write(text)


if __name__ == "__main__":
    main()
