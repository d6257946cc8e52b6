#!/usr/bin/env python3
"""The generation stage by the `simt` stage model with its L1/TEX term (simt/stage_l1.h), for the kernels before
63b5750 (60-byte G-buffer records read field by field) and after (64-byte records in 16-byte loads).

Usage:
  scripts/stage_l1_prediction.py [--model BIN] [--preset NAME]... [--md] TABLE.csv... > prediction.csv (or .md)

TABLE.csv: `scripts/gpu-check --stages` CSVs (results/stages/*/stages-*.csv); only the passes' descriptions are read
(scripts/stage_model_check.py's describe), never a measured time. Each distinct generation pass (scene, method,
tile) is priced per preset (default h100 and h200) with gbuffer=fields60 and gbuffer=wide64: the stage's modeled ms,
its generator kernel's terms (DRAM, issue, L1) and which decides, and the L1 wavefronts per warp of the generator
and tile_hits kernels. Every figure MODELED (simt), none measured. --md prints the same as a Markdown table.
"""
import argparse
import csv
import importlib.util
import pathlib
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent
_spec = importlib.util.spec_from_file_location("stage_model_check", ROOT / "scripts/stage_model_check.py")
check = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(check)

READS = ("fields60", "wide64")
TERMS = ("gen_dram_ms", "gen_issue_ms", "gen_l1_ms")


def passes(tables):
    """(scene, method, tile) -> the first row of each distinct generation pass."""
    out = {}
    for r in check.read_passes(tables):
        method = check.method_label(r).split("+")[0]  # a pass with an encoder generates as the one without
        out.setdefault((r["scene"], method, check.param(r["generator_params"], "tile") or "8x8"), r)
    return out


def model(binary, presets, rows):
    lines, keys = [], []
    for preset in presets:
        for read in READS:
            for i, r in enumerate(rows.values()):
                keys.append((preset, read, i))
                # the pass without its reordering (encoder none): only the generation stage is read
                fields = check.describe(r, preset, str(len(lines))).split(",")[:8]
                lines.append(",".join(fields + ["none", "0", "", read]))
    out = subprocess.run([binary], input="\n".join(lines) + "\n", capture_output=True, text=True, check=True).stdout
    return dict(zip(keys, csv.DictReader(out.splitlines())))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--model")
    ap.add_argument("--preset", action="append")
    ap.add_argument("--md", action="store_true")
    ap.add_argument("tables", nargs="+")
    args = ap.parse_args()
    presets = args.preset or ["h100", "h200"]
    rows = passes(args.tables)
    m = model(check.model_binary(args.model), presets, rows)
    header = ["kind", "preset", "gbuffer", "scene", "method", "tile", "gen_ms", "gen_dram_ms", "gen_issue_ms",
              "gen_l1_ms", "decides", "gen_l1_wavefronts", "tile_hits_l1_wavefronts"]
    table = []
    for preset in presets:
        for i, key in enumerate(rows):
            for read in READS:
                f = m[(preset, read, i)]
                decides = max(TERMS, key=lambda t: float(f[t]))[4:-3]
                table.append(["modeled", preset, read, *key, f["gen_ms"], *(f[t] for t in TERMS), decides,
                              f["gen_l1_wavefronts"], f["tile_hits_l1_wavefronts"]])
    if not args.md:
        w = csv.writer(sys.stdout, lineterminator="\n")
        w.writerows([header] + table)
        return
    print("## Generation stage of the h200-a26f7f6 passes with the L1/TEX term, before (fields60) and after (wide64) "
          "63b5750 (MODELED: simt stage model; UNMEASURED)\n")
    print("Generator kernel terms in ms; L1 wavefronts per warp (generator / tile_hits); `decides`: the largest term "
          "of the generator kernel.\n")
    print("| preset | scene | method | tile | gen ms before | gen ms after | after / before | decides (before, after) "
          "| L1 ms before | L1 ms after | issue ms before | issue ms after | L1 wavefronts / warp before | after |")
    print("|---|---|---|---|---:|---:|---:|---|---:|---:|---:|---:|---:|---:|")
    for b, a in zip(table[0::2], table[1::2]):
        print(f"| {b[1]} | {b[3]} | {b[4]} | {b[5]} | {float(b[6]):.4f} | {float(a[6]):.4f} | "
              f"{float(a[6]) / float(b[6]):.3f} | {b[10]}, {a[10]} | {float(b[9]):.4f} | {float(a[9]):.4f} | "
              f"{float(b[8]):.4f} | {float(a[8]):.4f} | {b[11]} / {b[12]} | {a[11]} / {a[12]} |")


if __name__ == "__main__":
    main()
