#!/usr/bin/env python3
"""The `simt` stage model (simt/stage_model.h) of the measured device passes, and later beside them.

Usage:
  scripts/stage_model_check.py predict [--model BIN] [--preset NAME] TABLE.csv... > prediction.csv

TABLE.csv: `raycoh table` / `raycoh sweep` CSVs of a `scripts/gpu-check --stages` run (results/stages/*/stages-*.csv).
Their `cuda` secondary rows of the materialized pipeline (pipeline=device) describe each pass: resolution, rays,
generator and its tiles, encoder and key bits, and the gather's bytes (modeled_permute_bytes, counted from the
pass's own order). Only those descriptions go to the model (raycoh_stage_model, built from simt/stage_model_main.cpp;
default build-h41/simt/, else build/simt/): no measured time is read by `predict`.
Printed: one line per pass and stage that ran, every figure MODELED (kind = modeled).
"""
import argparse
import csv
import os
import pathlib
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent
STAGES = ("gen", "key", "sort", "permute")


def param(text, name):
    for part in (text or "").split(","):
        if part.startswith(name + "="):
            return part[len(name) + 1:]
    return None


def read_passes(paths):
    """The measured device passes (rows), each with the file it came from."""
    rows = []
    for p in paths:
        with open(p, newline="") as f:
            for r in csv.DictReader(f):
                if r.get("run_under") or r.get("pass") != "secondary" or r.get("tracer") != "cuda":
                    continue
                if r.get("pipeline") != "device":
                    continue
                r["_file"] = os.path.basename(p)
                rows.append(r)
    return rows


def method_label(r):
    """As scripts/stage_bounds.py: a sweep row is named by its generator's parameters."""
    if r["_file"].startswith("stages-sweep"):
        return f"{r['generator']}:{r['generator_params'].split(',seed=')[0]}"
    return r["method"]


def describe(r, preset, label):
    """raycoh_stage_model's input line for the pass of row r."""
    tile = (param(r["generator_params"], "tile") or "8x8").split("x")
    generator = "noopt" if r["generator"] == "noopt" else "group"
    encoder = r.get("encoder") or "none"
    bits = param(r.get("encoder_params"), "bits") or "0"
    permute = r.get("modeled_permute_bytes", "") if r.get("permute") == "physical" else ""
    return ",".join([label, preset, r["width"], r["height"], r["rays"], generator, tile[0], tile[1], encoder, bits,
                     permute])


def model_binary(given):
    builds = [ROOT / "build-h41/simt/raycoh_stage_model", ROOT / "build/simt/raycoh_stage_model"]
    for c in ([given] if given else []) + builds:
        if c and os.access(c, os.X_OK):
            return str(c)
    sys.exit("stage_model_check.py: no raycoh_stage_model (build it, or pass --model)")


def predict(args):
    rows = read_passes(args.tables)
    lines = [describe(r, args.preset, str(i)) for i, r in enumerate(rows)]
    out = subprocess.run([model_binary(args.model)], input="\n".join(lines) + "\n", capture_output=True, text=True,
                         check=True).stdout
    modeled = {m["label"]: m for m in csv.DictReader(out.splitlines())}
    w = csv.writer(sys.stdout, lineterminator="\n")
    w.writerow(["kind", "preset", "file", "scene", "method", "stage", "rays", "generator", "tile", "encoder",
                "key_bits", "modeled_ms"])
    for i, r in enumerate(rows):
        m = modeled[str(i)]
        for stage in STAGES:
            ms = float(m[f"{stage}_ms"])
            if ms <= 0:
                continue
            w.writerow(["modeled", args.preset, r["_file"], r["scene"], method_label(r), stage, r["rays"],
                        r["generator"], param(r["generator_params"], "tile") or "", r.get("encoder") or "none",
                        param(r.get("encoder_params"), "bits") or "", f"{ms:.6f}"])


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = ap.add_subparsers(dest="command", required=True)
    p = sub.add_parser("predict")
    p.add_argument("--model")
    p.add_argument("--preset", default="h200")
    p.add_argument("tables", nargs="+")
    p.set_defaults(run=predict)
    args = ap.parse_args(argv[1:])
    args.run(args)


if __name__ == "__main__":
    main(sys.argv)
