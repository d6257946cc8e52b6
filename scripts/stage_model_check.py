#!/usr/bin/env python3
"""The `simt` stage model (simt/stage_model.h) of the measured device passes, and later beside them.

Usage:
  scripts/stage_model_check.py predict [--model BIN] [--preset NAME] [--gbuffer wide64|fields60] TABLE.csv...
      > prediction.csv

TABLE.csv: `raycoh table` / `raycoh sweep` CSVs of a `scripts/gpu-check --stages` run (results/stages/*/stages-*.csv).
Their `cuda` secondary rows of the materialized pipeline (pipeline=device) describe each pass: resolution, rays,
generator and its tiles, encoder and key bits, and the gather's bytes (modeled_permute_bytes, counted from the
pass's own order). Only those descriptions go to the model (raycoh_stage_model, built from simt/stage_model_main.cpp;
default build/simt/): no measured time is read by `predict`.
--gbuffer: the generation kernels priced (simt/stage_l1.h GBufferRead): wide64, those since 63b5750, or fields60, the
earlier ones that made the runs up to it (h200-a26f7f6); without it the model's default (wide64).
--trip-counts: the group kernel priced by its trip-counted count (simt/stage_paths.h): each pass's k, hybrid rule
and frame (generator_params) and its group counts (groups_glossy + groups_hybrid + groups_independent, and
groups_hybrid: workload columns of the row, never a time) go to the model as its five path fields.
--mlhcc-walks WALKS.csv (with --trip-counts): bench/mlhcc_walks.cpp's counts per scene (origin_trips, end_trips:
each cut walk's iterations per warp, counted on the CPU's copy of the pass) price MLHCC's key kernel by its
trip-counted count.
--noopt-path (with --trip-counts): the noopt kernel priced by its path (simt/stage_paths.h NooptPath): the warps
holding a glossy-like or transmissive lane from the scene's group counts in its `ours` row of the same table
(the same G-buffer: groups_glossy + groups_hybrid, groups_independent).
--latency (with --trip-counts): the generator and key kernels get the latency term (simt/stage_latency.h; results/
model/stage-latency/): a block's dependent chain times the blocks that run one after another on an SM.
--terms FILE: also writes each pass's kernel terms as raycoh_stage_model prints them (gen_dram_ms, gen_issue_ms,
gen_l1_ms, gen_latency_ms, key_latency_ms, ...), one line per pass, MODELED.
Printed: one line per pass and stage that ran, every figure MODELED (kind = modeled).

  scripts/stage_model_check.py compare [--ncu LOG.xz] [--l1-term] PREDICTION.csv TABLE.csv... > model-vs-measured.md

Sets every measured stage (GPU: the row's gen_ms, key_ms, sort_ms, permute_ms, medians of the run's repeats) beside
its modeled figure from PREDICTION.csv (`predict`'s output, committed before the comparison) with modeled /
measured, says which agree within ±25% and, for each miss, which part of the kernel the model leaves out
(docs/simt-model.md section 3, "Not modeled"). Measured and modeled figures stand side by side, never added.
With --ncu LOG.xz (an Nsight Compute CSV log of the same kernels, e.g. results/stages/h200-6ebd003/ncu-stages.log.xz)
it adds what bounded each profiled kernel (measured, under the profiler's clocks): the evidence for the reasons.
--l1-term: PREDICTION.csv is of the model with its L1/TEX term (results/model/stage-l1-term/): the reasons say so.
--trip-counts: PREDICTION.csv is of the model with the trip-counted group kernel and MLHCC key
(results/model/stage-trip-counts/; implies --l1-term): the reasons say what that model still leaves out.
--noopt-path (with --trip-counts): the noopt kernel too is priced by its path (results/model/stage-trip-counts/
noopt-path/): its reason says so.
--latency (with --trip-counts --noopt-path): the generator and key kernels have the latency term (results/model/
stage-latency/): the reasons say what is left with it.
"""
import argparse
import csv
import lzma
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


def group_path(r):
    """The five path fields of a group-kernel pass: k, hybrid, frame, non-diffuse groups, hybrid groups."""
    params = r["generator_params"]
    groups = sum(float(r.get(f"groups_{t}") or 0) for t in ("glossy", "hybrid", "independent"))
    return [param(params, "k") or "8", param(params, "hybrid") or "paper", param(params, "frame") or "duff",
            f"{groups:.0f}", r.get("groups_hybrid") or "0"]


def scene_groups(rows):
    """scene -> (glossy-like groups, transmissive groups) of its `ours` pass (stages-SCENE.csv)."""
    out = {}
    for r in rows:
        if r["method"] == "ours" and not r["_file"].startswith("stages-sweep"):
            out[r["scene"]] = (float(r["groups_glossy"] or 0) + float(r["groups_hybrid"] or 0),
                               float(r["groups_independent"] or 0))
    return out


def describe(r, preset, label, gbuffer=None, trips=False, walks=None, lobes=None, latency=False):
    """raycoh_stage_model's input line for the pass of row r: its 11 workload fields, then (gbuffer, or trips) the
    12th, the G-buffer read (wide64 if not given); trips: the group kernel's five path fields after it, then the
    walks' two (with walks, lobes or latency) and the lobes' two (with lobes or latency), empty for a scene not
    given; latency (implies trips): the 22nd field, 1."""
    trips = trips or latency
    tile = (param(r["generator_params"], "tile") or "8x8").split("x")
    generator = "noopt" if r["generator"] == "noopt" else "group"
    encoder = r.get("encoder") or "none"
    bits = param(r.get("encoder_params"), "bits") or "0"
    permute = r.get("modeled_permute_bytes", "") if r.get("permute") == "physical" else ""
    fields = [label, preset, r["width"], r["height"], r["rays"], generator, tile[0], tile[1], encoder, bits, permute]
    if trips or gbuffer:
        fields.append(gbuffer or "wide64")
    if trips:
        fields += group_path(r)
        if walks is not None or lobes or latency:
            fields += list((walks or {}).get(r["scene"], ("", "")))
        if lobes or latency:
            fields += [f"{x:.0f}" for x in lobes[r["scene"]]] if lobes else ["", ""]
    if latency:
        fields.append("1")
    return ",".join(fields)


def model_binary(given):
    builds = [ROOT / "build/simt/raycoh_stage_model"]
    for c in ([given] if given else []) + builds:
        if c and os.access(c, os.X_OK):
            return str(c)
    sys.exit("stage_model_check.py: no raycoh_stage_model (build it, or pass --model)")


def predict(args):
    rows = read_passes(args.tables)
    walks = None
    if args.mlhcc_walks:
        with open(args.mlhcc_walks, newline="") as f:
            walks = {w["scene"]: (w["origin_trips"], w["end_trips"]) for w in csv.DictReader(f)}
    lobes = scene_groups(rows) if args.noopt_path else None
    if args.latency and not args.trip_counts:
        sys.exit("stage_model_check.py: --latency needs --trip-counts")
    lines = [describe(r, args.preset, str(i), args.gbuffer, args.trip_counts, walks, lobes, args.latency)
             for i, r in enumerate(rows)]
    out = subprocess.run([model_binary(args.model)], input="\n".join(lines) + "\n", capture_output=True, text=True,
                         check=True).stdout
    modeled = {m["label"]: m for m in csv.DictReader(out.splitlines())}
    if args.terms:
        with open(args.terms, "w", newline="") as f:
            t = csv.writer(f, lineterminator="\n")
            columns = [c for c in next(iter(modeled.values())) if c != "label"]
            t.writerow(["kind", "preset", "file", "scene", "method"] + columns)
            for i, r in enumerate(rows):
                t.writerow(["modeled", args.preset, r["_file"], r["scene"], method_label(r)] +
                           [modeled[str(i)][c] for c in columns])
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


TOLERANCE = 0.25


NOOPT_L1 = ("noopt generation: the model with its L1 term prices this kernel issue-bound; the L1 term (the L1-hit "
            "wavefronts of its 60-byte records read field by field, the batch's stores) is a third of the issue "
            "term, so the L1/TEX load Nsight Compute measured (below) is work that rule does not count (the miss "
            "path: fills from L2, misses in flight), at half occupancy (62 registers); tile_hits reads the whole "
            "G-buffer from DRAM, not the one sector per pixel the model counts")


TRIP_REASONS = {
    ("gen", True): ("group kernel, trip-counted: priced at the issue rate, but its one-thread-per-group phases (the "
                    "census, positions and mean vote: k iterations of dependent shared-memory loads per group) and "
                    "the barriers between phases are latency the model leaves out; in those phases only the warps "
                    "holding group threads work (1 of 2 on 8x8 tiles, 1 of 8 on 16x16 and 32x8) while the others "
                    "wait at the barrier, so the gap grows with k and with the tile"),
    ("gen", False): ("group kernel, trip-counted: every warp is counted with a group off the all-diffuse path "
                     "(the bound of one warp per such group, here reached), and the straight-line unrolled blocks "
                     "once each"),
    ("key", True): ("mlhcc, trip-counted: the walks' iterations are counted (mlhcc-walks.csv) and priced at the issue "
                    "rate, but each iteration loads a BVH node and its cut, which the next iteration needs "
                    "(a dependent chain of global loads per level: latency, not modeled), so the deeper the walks "
                    "the larger the gap"),
}


NOOPT_PATH = ("noopt generation, per path: a warp runs its common code and the lobes its lanes hold (on sibenik and "
              "conference the diffuse case alone), which puts its issue term below its bytes there (the G-buffer read, "
              "the batch written); the GPU is bound by neither: Nsight Compute (below) has its L1/TEX pipeline at 77% "
              "at half occupancy (62 registers), the load the L1 term's hit rule does not count (each record's sectors "
              "missing once, fills from L2, the batch's write-through stores), and tile_hits reads the whole G-buffer "
              "record, not the one sector per pixel the model counts")


LATENCY_REASONS = {
    "gen": ("group kernel with the latency term: here its chain (the group threads' serial loops over k slots and "
            "members, a block's phases in turn) is at or below its issue term, or just above it, and what the model "
            "lacks does not grow with k: these are the passes at small k (k = 8 on every tile; on tiles of more "
            "than 64 pixels k = 16 and 32 too, where the chain decides yet grows with k faster than the measured "
            "time, so the gap is at small k); the per-pixel half of the kernel (the G-buffer record read, the batch "
            "written) is the noopt kernel's work, whose L1/TEX miss path no term has (noopt misses by about as "
            "much, below; Nsight Compute has the group kernel's L1/TEX at 47%), and the chain's ALU and load "
            "latencies are the A100's"),
    "key": ("mlhcc with the latency term: its walk's chain (three dependent loads an iteration, taken as L1 hits, "
            "at 48 resident warps a SM) stays under its issue term, so the latency term decides nothing here; "
            "sibenik's deeper walks reach deeper BVH levels, whose nodes the L1-hit assumption and the absent L1 "
            "term of the key kernel (32 lanes loading up to 32 different nodes a step) do not price"),
    "noopt": ("noopt generation, per path, with the latency term: its chain (the record from DRAM, the material, "
              "the block scan, its path's instructions) is under its bytes, so the term decides nothing; the L1/TEX "
              "miss path (Nsight Compute: 77% of L1/TEX at half occupancy, below) is what no term models"),
}


def reason(stage, r, ratio, l1_term=False, trips=False, noopt_path=False, latency=False):
    """Why a stage misses (ratio = modeled / measured): the model's known gaps for that kernel."""
    low = ratio < 1
    if latency and low and stage == "gen":
        return LATENCY_REASONS["noopt" if r["generator"] == "noopt" else "gen"]
    if latency and low and stage == "key" and r.get("encoder") == "mlhcc":
        return LATENCY_REASONS["key"]
    if trips and stage == "gen" and r["generator"] != "noopt":
        return TRIP_REASONS[("gen", low)]
    if trips and stage == "key" and r.get("encoder") == "mlhcc" and low:
        return TRIP_REASONS[("key", True)]
    if noopt_path and stage == "gen" and r["generator"] == "noopt" and low:
        return NOOPT_PATH
    if (l1_term or trips) and stage == "gen" and r["generator"] == "noopt" and low:
        return NOOPT_L1
    if stage == "gen" and r["generator"] != "noopt":
        k = param(r["generator_params"], "k") or "8"
        if low:
            return (f"group kernel, k={k}: its per-slot loops (every pixel ranks itself over its group's k slots; "
                    "one thread per group walks the k members in the census, positions and mean) run k times and "
                    "are counted once, and the one-thread-per-group phases stall the tile's other warps at the "
                    "barriers (latency, not modeled): both grow with k")
        return ("group kernel: the static count holds every branch (each hybrid rule, frame and order, the "
                "glossy-member loop with its lobe sampling); a thread runs a fraction of it")
    if stage == "gen":
        return ("noopt generation: " + ("its kernel is bound by neither of the model's terms: the L1/TEX pipeline "
                                        "is its busiest unit (the 60-byte G-buffer records read field by field, "
                                        "the batch's columns written) at half occupancy (62 registers), and "
                                        "tile_hits reads the whole G-buffer from DRAM, not the one sector per pixel "
                                        "the model counts (Nsight Compute, below); the stage model has no L1 term"
                                        if low else "the static count holds every lobe's code; a thread samples one"))
    if stage == "key" and r.get("encoder") == "mlhcc" and low:
        return ("mlhcc: the cut walk (mlhcc_write_path) descends the BVH once per point, origin and end point, a "
                "134-instruction loop body per BVH level until the key's 32 bits are full; the count holds each "
                "walk's body once, the GPU runs it once per level descended (tens of levels; scene-dependent)")
    if stage == "sort" and low:
        return ("onesweep: the pass floor is CUB's on an RTX 3090 with 65 K 16-bit keys; a pass of 2 M key-value "
                "pairs on the H200 costs more than that floor plus its bytes (stages.md: our sort is CUB's own "
                "time, so the gap is the model's, not our use of CUB)")
    if stage == "permute" and low:
        return ("gather: its bytes are counted exactly from the order, but scattered 32-byte sector reads reach "
                "less than the streaming bandwidth the model prices them at (the more scattered the order, the "
                "larger the gap)")
    return ("the model prices this kernel above its measured time: an instruction or byte count that the GPU "
            "does not pay in full" if not low else "latency the model leaves out")


NCU = (("Duration", "duration ns"), ("SM Frequency", "SM clock Hz"), ("Compute (SM) Throughput", "SM %"),
       ("L1/TEX Cache Throughput", "L1/TEX %"), ("DRAM Throughput", "DRAM %"), ("Achieved Occupancy", "occupancy %"),
       ("Registers Per Thread", "registers"), ("Warp Cycles Per Issued Instruction", "cycles per issue"))


def ncu_table(path):
    """Each profiled kernel's first launch: the metrics of NCU, from an Nsight Compute --csv log."""
    first, metrics = {}, {}
    with lzma.open(path, "rt") as f:
        for r in csv.reader(f):
            if len(r) < 15 or not r[0].isdigit():
                continue
            name = r[4].split("(")[0].split("::")[-1].split("<")[0]
            if name.startswith("fused_"):  # no stage of its own (the fused pipeline)
                continue
            first.setdefault(name, r[0])
            if first[name] == r[0] and r[12] in dict(NCU) and r[12] not in metrics.setdefault(name, {}):
                metrics[name][r[12]] = r[14]
    out = [f"## What bounded each generation kernel (measured: Nsight Compute, `{os.path.basename(path)}`)", "",
           "| kernel | " + " | ".join(label for _, label in NCU) + " |", "|---|" + "---:|" * len(NCU)]
    for name, m in metrics.items():
        out.append(f"| {name} | " + " | ".join(m.get(metric, "") for metric, _ in NCU) + " |")
    return out + [""]


def compare(args):
    with open(args.prediction, newline="") as f:
        modeled = {(m["file"], m["scene"], m["method"], m["stage"]): float(m["modeled_ms"]) for m in csv.DictReader(f)}
    rows = read_passes(args.tables)
    out = ["## Device stages: measured (GPU) beside modeled (simt)", "",
           f"Measured: the rows' stage medians (GPU). Modeled: `{os.path.basename(args.prediction)}` (simt stage "
           f"model, preset {next(iter(csv.DictReader(open(args.prediction))))['preset']}). Within ±25%: "
           f"|modeled / measured − 1| <= {TOLERANCE}.", "",
           "| scene | method | stage | measured ms (GPU) | modeled ms (simt) | modeled / measured | within ±25% |",
           "|---|---|---|---:|---:|---:|---|"]
    tally, misses, lucky = {}, {}, []
    for r in rows:
        for stage in STAGES:
            ms = float(r.get(f"{stage}_ms") or 0)
            key = (r["_file"], r["scene"], method_label(r), stage)
            if ms <= 0 or key not in modeled:
                continue
            ratio = modeled[key] / ms
            hit = abs(ratio - 1) <= TOLERANCE
            n, k, lo, hi = tally.get(stage, (0, 0, ratio, ratio))
            tally[stage] = (n + 1, k + hit, min(lo, ratio), max(hi, ratio))
            if not hit:
                why = reason(stage, r, ratio, args.l1_term, args.trip_counts, args.noopt_path, args.latency)
                misses.setdefault(why, []).append((ratio, r["scene"], key[2], stage))
            elif stage == "gen" and r["generator"] != "noopt":
                lucky.append(f"{key[2]} ({ratio:.2f})")
            out.append(f"| {r['scene']} | {key[2]} | {stage} | {ms:.4f} | {modeled[key]:.4f} | {ratio:.2f} | "
                       f"{'yes' if hit else 'no'} |")
    out += ["", "## Summary", "", "| stage | stages | within ±25% | modeled / measured, lowest … highest |",
            "|---|---:|---:|---|"]
    for stage in STAGES:
        if stage in tally:
            n, k, lo, hi = tally[stage]
            out.append(f"| {stage} | {n} | {k} | {lo:.2f} … {hi:.2f} |")
    total = sum(t[0] for t in tally.values())
    within = sum(t[1] for t in tally.values())
    out.append(f"| all | {total} | {within} | |")
    out += ["", "## The misses and what the model leaves out", ""]
    for why, cases in sorted(misses.items(), key=lambda kv: -len(kv[1])):
        ratios = [c[0] for c in cases]
        out.append(f"- {len(cases)} stage(s), modeled / measured {min(ratios):.2f} … {max(ratios):.2f}: {why}.")
    if lucky and args.trip_counts:
        out += ["", f"Group-kernel generations within ±25% ({len(lucky)}): {', '.join(lucky)}."]
    elif lucky:
        out += ["", f"Group-kernel generations within ±25% ({len(lucky)}: {', '.join(lucky)}) are where the static "
                "count's surplus branches and its single count of the k-fold loops happen to cancel: two errors in "
                "opposite directions, not evidence that the group kernel is modeled."]
    if args.ncu:
        out += [""] + ncu_table(args.ncu)
    print("\n".join(out))


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = ap.add_subparsers(dest="command", required=True)
    p = sub.add_parser("predict")
    p.add_argument("--model")
    p.add_argument("--preset", default="h200")
    p.add_argument("--gbuffer", choices=("wide64", "fields60"))
    p.add_argument("--trip-counts", action="store_true")
    p.add_argument("--mlhcc-walks")
    p.add_argument("--noopt-path", action="store_true")
    p.add_argument("--latency", action="store_true")
    p.add_argument("--terms")
    p.add_argument("tables", nargs="+")
    p.set_defaults(run=predict)
    c = sub.add_parser("compare")
    c.add_argument("--ncu")
    c.add_argument("--l1-term", action="store_true")
    c.add_argument("--trip-counts", action="store_true")
    c.add_argument("--noopt-path", action="store_true")
    c.add_argument("--latency", action="store_true")
    c.add_argument("prediction")
    c.add_argument("tables", nargs="+")
    c.set_defaults(run=compare)
    args = ap.parse_args(argv[1:])
    args.run(args)


if __name__ == "__main__":
    main(sys.argv)
