#!/usr/bin/env python3
"""The `simt` stage model's generation times of two model builds side by side (before / after a kernel change).

Usage:
  scripts/stage_model_diff.py --before BIN --after BIN [--preset NAME]... [--title TEXT] TABLE.csv... > prediction.md

BIN: raycoh_stage_model built from the revision before and after the change (simt/stage_model_main.cpp).
TABLE.csv: the `scripts/gpu-check --stages` CSVs whose passes are priced (as scripts/stage_model_check.py predict:
only the passes' descriptions are read, never a measured time). Each distinct generation pass (scene, generator and
its parameters) is one row: per preset, the modeled generation ms of each build and after / before. Every figure
is MODELED (simt), none measured.
"""
import argparse
import csv
import pathlib
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent


def generation(binary, preset, tables):
    """(scene, method) -> modeled gen ms of `binary` on `preset`, one entry per distinct generation pass."""
    out = subprocess.run([sys.executable, str(ROOT / "scripts/stage_model_check.py"), "predict", "--model", binary,
                          "--preset", preset, *tables], capture_output=True, text=True, check=True).stdout
    rows = {}
    for r in csv.DictReader(out.splitlines()):
        if r["stage"] == "gen":
            method = r["method"].split("+")[0]  # a pass with an encoder generates as the one without
            rows.setdefault((r["scene"], method, r["tile"]), float(r["modeled_ms"]))
    return rows


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--before", required=True)
    ap.add_argument("--after", required=True)
    ap.add_argument("--preset", action="append")
    ap.add_argument("--title", default="Generation stage, modeled before and after")
    ap.add_argument("tables", nargs="+")
    args = ap.parse_args()
    presets = args.preset or ["h100", "h200"]
    figures = {p: (generation(args.before, p, args.tables), generation(args.after, p, args.tables)) for p in presets}
    keys = list(figures[presets[0]][0])
    print(f"## {args.title} (MODELED: simt stage model; UNMEASURED)\n")
    print("| scene | method | tile | " + " | ".join(f"{p} before ms | {p} after ms | {p} after / before"
                                                    for p in presets) + " |")
    print("|---|---|---|" + "---:|---:|---:|" * len(presets))
    for key in keys:
        cells = []
        for p in presets:
            before, after = figures[p][0][key], figures[p][1][key]
            cells += [f"{before:.4f}", f"{after:.4f}", f"{after / before:.3f}"]
        print(f"| {key[0]} | {key[1]} | {key[2] or '8x8'} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
