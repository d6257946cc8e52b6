#!/usr/bin/env python3
"""Each measured device stage beside what its bytes allow, and the materialized pipeline against the fused one.

Usage: scripts/stage_bounds.py STAGE_BOUNDS.csv TABLE.csv... > stages.md

STAGE_BOUNDS.csv is raycoh_bench_stages' output (bench/stage_bounds.cu: copy bandwidth, launch gap and CUB's own
sort time, measured on the GPU of the run); the tables are `raycoh table` / `raycoh sweep` CSVs of the same run
whose `cuda` rows carry measured stage times (gen_ms, key_ms, sort_ms, permute_ms, trace_ms, gpu_e2e_ms) and the
bytes each stage moved (modeled_*_bytes: simt/pipeline_model.h's traffic of that pass).

Printed (markdown, every figure computed from the rows):
  1. the device facts;
  2. per materialized pass (pipeline=device) and stage: measured ms, MB moved, bound = bytes / measured copy
     bandwidth (the faster of the bench's copy kernel and cudaMemcpy), and measured / bound (the goal: <= 2); the sort beside CUB's own time for the same key bits
     (the goal: <= 1.2);
  3. end to end per scene and method, materialized and fused (pipeline=fused): the measured span (gpu_e2e_ms) and
     each ratio to noopt of the same pipeline, beside the trace-only ratio of the materialized pass; fused / trace
     ratio is the share of the trace's coherence gain that survives end to end (the goal: >= 0.95); the
     reorderings (noopt+encoder) have no fused form and show the materialized columns only;
  4. the verdict per scene: the methods ordered by measured end-to-end time, materialized and fused together.
Rows read: pass = secondary, tracer = cuda, pipeline in (device, fused); rows run under a profiler or sanitizer
are excluded (their run_under column, and for older files without it, files named ncu-*).
"""
import csv
import os
import sys
from collections import defaultdict

import speed_interval

STAGES = (("gen", "gen_ms", "modeled_gen_bytes"), ("key", "key_ms", "modeled_key_bytes"),
          ("sort", "sort_ms", "modeled_sort_bytes"), ("permute", "permute_ms", "modeled_permute_bytes"))


def num(row, col):
    v = row.get(col, "")
    try:
        return float(v) if v != "" else None
    except ValueError:
        return None


def key_bits(row):
    for part in row.get("encoder_params", "").split(","):
        if part.startswith("bits="):
            return int(part[5:])
    return None


def read_bounds(path):
    facts = {"cub": {}}
    with open(path, newline="") as f:
        for r in csv.DictReader(f):
            if r["measure"] == "cub_sort":
                facts["cub"][int(r["bits"])] = float(r["median_ms"])
            else:
                facts[r["measure"]] = r
    return facts


def copy_gb_s(facts):
    """The device's copy bandwidth: the faster of the bench's copy kernel and cudaMemcpy (GB/s); None without."""
    rates = [float(facts[m]["gb_s"]) for m in ("copy", "memcpy") if m in facts and facts[m].get("gb_s")]
    return max(rates) if rates else None


def read_rows(paths):
    rows = []
    for p in paths:
        if os.path.basename(p).startswith("ncu-") or not os.path.exists(p):
            continue
        with open(p, newline="") as f:
            for r in csv.DictReader(f):
                if r.get("run_under"):  # under a profiler or sanitizer: not a timing
                    continue
                if r.get("pass") == "secondary" and r.get("tracer") == "cuda" and r.get("pipeline") in (
                        "device", "fused"):
                    r["_file"] = os.path.basename(p)
                    rows.append(r)
    return rows


def method_label(r):
    m = r["method"]
    if r.get("_file", "").startswith("stages-sweep"):
        m = f"{r['generator']}:{r['generator_params'].split(',seed=')[0]}"
    return m


def stage_interval(r, stage):
    """(lo, hi): the stage's median interval from the row's repeats (<stage>_samples_ms), None without them."""
    samples = r.get(f"{stage}_samples_ms", "")
    if not samples:
        return None
    _, lo, hi, _ = speed_interval.median_interval([float(x) for x in samples.split(";")])
    return lo, hi


def stage_table(rows, facts, out):
    bw = copy_gb_s(facts)  # None: no bounds (the bench did not run), the stages alone
    # Rows that keep every pass's stage times get each stage's 95% interval (scripts/speed_interval.py); the
    # verdict against the bound (<= 2) is then read from the interval's upper end.
    intervals = any(r.get("gen_samples_ms") for r in rows)
    out.append("| scene | method | stage | measured ms | MB moved | bound ms | measured / bound |"
               + (" upper end / bound |" if intervals else ""))
    out.append("|---|---|---|---:|---:|---:|---:|" + ("---:|" if intervals else ""))
    worst = defaultdict(float)
    for r in rows:
        if r["pipeline"] != "device":
            continue
        for stage, ms_col, bytes_col in STAGES:
            ms, b = num(r, ms_col), num(r, bytes_col)
            if ms is None or b is None or b <= 0 or ms <= 0:
                continue
            bound = b / (bw * 1e6) if bw else None
            if bound:
                worst[stage] = max(worst[stage], ms / bound)
            iv = stage_interval(r, stage)
            line = (f"| {r['scene']} | {method_label(r)} | {stage} | {ms:.4f}"
                    + (f" [{iv[0]:.4f}, {iv[1]:.4f}]" if iv else "") + f" | {b / 1e6:.1f} | "
                    + (f"{bound:.4f} | {ms / bound:.2f} |" if bound else " | |"))
            if intervals:
                line += f" {iv[1] / bound:.2f} |" if iv and bound else " |"
            out.append(line)
    out.append("")
    out.append("Worst measured / bound per stage (goal <= 2): " +
               (", ".join(f"{s} {v:.2f}" for s, v in sorted(worst.items())) or "no bounds"))
    out.append("")
    if not facts["cub"]:  # no CUB times to set the sorts beside
        return
    out.append("| scene | method | key bits | sort measured ms | CUB alone ms | measured / CUB |")
    out.append("|---|---|---:|---:|---:|---:|")
    for r in rows:
        bits, ms = key_bits(r), num(r, "sort_ms")
        if r["pipeline"] != "device" or not bits or not ms or bits not in facts["cub"]:
            continue
        cub = facts["cub"][bits]
        out.append(f"| {r['scene']} | {method_label(r)} | {bits} | {ms:.4f} | {cub:.4f} | {ms / cub:.2f} |")
    out.append("")


def e2e_table(rows, out):
    by = {}  # (scene, method, pipeline, file): each ratio is taken within one table (its own noopt row)
    for r in rows:
        if not r["_file"].startswith("stages-sweep"):
            by[(r["scene"], r["method"], r["pipeline"], r["_file"])] = r
    out.append("| scene | method | trace-only ×noopt (materialized) | e2e ms materialized | ×noopt | e2e ms fused | "
               "×noopt | fused ×noopt / trace ×noopt |")
    out.append("|---|---|---:|---:|---:|---:|---:|---:|")
    for (scene, method, pipeline, f), r in sorted(by.items()):
        if pipeline != "device" or (method == "noopt" and "encoders" in f):
            continue
        base, fused, fbase = (by.get((scene, "noopt", "device", f)), by.get((scene, method, "fused", f)),
                              by.get((scene, "noopt", "fused", f)))
        if not base:
            continue
        trace = num(base, "trace_ms") / num(r, "trace_ms")
        mat = num(r, "gpu_e2e_ms")
        mat_ratio = num(base, "gpu_e2e_ms") / mat
        cells = [f"{trace:.3f}", f"{mat:.4f}", f"{mat_ratio:.3f}"]
        if fused and fbase:
            f_ms = num(fused, "gpu_e2e_ms")
            f_ratio = num(fbase, "gpu_e2e_ms") / f_ms
            cells += [f"{f_ms:.4f}", f"{f_ratio:.3f}", f"{f_ratio / trace:.3f}"]
        else:
            cells += ["", "", ""]
        out.append(f"| {scene} | {method} | " + " | ".join(cells) + " |")
    out.append("")
    # Fused against materialized, method by method: medians of one run, no interval.
    gaps = [(1 - num(by[(s, m, "fused", f)], "gpu_e2e_ms") / num(r, "gpu_e2e_ms"), s, m)
            for (s, m, p, f), r in by.items() if p == "device" and (s, m, "fused", f) in by]
    if gaps:
        below = sum(g > 0 for g, _, _ in gaps)
        g, s, m = min(gaps)
        out.append(f"Fused span below the materialized span (medians of this run, no interval): {below} of "
                   f"{len(gaps)} scene x method pairs; the smallest difference {g * 100:.1f}% ({s}, {m}).")
        out.append("")


def verdict(rows, out):
    by_scene, seen = defaultdict(list), set()
    # The main tables first: their noopt row stands for noopt (the encoder tables measure it again).
    for r in sorted(rows, key=lambda r: "encoders" in r["_file"]):
        if r["_file"].startswith("stages-sweep") or num(r, "gpu_e2e_ms") is None:
            continue
        label = r["method"] + (" (fused)" if r["pipeline"] == "fused" else "")
        if (r["scene"], label) in seen:
            continue
        seen.add((r["scene"], label))
        by_scene[r["scene"]].append((num(r, "gpu_e2e_ms"), label, r))
    out.append("## Verdict: fastest end to end per scene (measured spans, median of the run's repeats)")
    out.append("")
    for scene, entries in sorted(by_scene.items()):
        entries.sort()
        out.append(f"- {scene}: " + " < ".join(f"{label} {ms:.4f} ms" for ms, label, _ in entries))
        ranked = [(label, speed_interval.series([r], True)) for _, label, r in entries]
        base = dict(ranked).get("noopt")
        if base:  # the same words, and intervals, as raycoh's table and report (docs/statistics.md)
            out.append(f"  - at 95%: {speed_interval.top_of_ranking(ranked, base)}")
    out.append("")


def device_facts(facts, path, out):
    """The bench's lines; without its CSV (or its copy rows) one line says so and the stages follow without bounds."""
    copy, memcpy, launch = facts.get("copy"), facts.get("memcpy"), facts.get("launch")
    if copy_gb_s(facts) is None:
        out.append(f"No stage bounds: {path} is missing or holds no copy bandwidth (raycoh_bench_stages did not run "
                   "or failed: its step's log says why); the stages follow without their bounds.")
    if copy:
        out.append(f"Copy bandwidth (copy kernel, median of the bench's runs): {float(copy['gb_s']):.0f} GB/s"
                   + (f"; cudaMemcpy device to device: {float(memcpy['gb_s']):.0f} GB/s" if memcpy else "")
                   + (f"; back-to-back launch gap: {float(launch['median_ms']) * 1e3:.2f} us" if launch else "") + ".")
    if facts["cub"]:
        out.append("CUB SortPairs alone, " + ", ".join(f"{b} bits {ms:.4f} ms" for b, ms in sorted(facts["cub"].items()))
                   + ".")
    out.append("")


def main(argv):
    if len(argv) < 3:
        sys.exit("usage: stage_bounds.py STAGE_BOUNDS.csv TABLE.csv...")
    facts = read_bounds(argv[1]) if os.path.isfile(argv[1]) else {"cub": {}}
    rows = read_rows(argv[2:])
    # A simulator build's rows (device "simulated: GPGPU-Sim ...", scripts/gpu-check dry-run) are not measurements.
    simulated = any(r.get("device", "").startswith("simulated") for r in rows)
    out = ["## Device stages beside their bounds (" + ("SIMULATED (GPGPU-Sim), not hardware" if simulated else
                                                      "measured") + ")", ""]
    device_facts(facts, argv[1], out)
    if not rows:
        out.append("(no measured device rows in the tables)")
    else:
        stage_table(rows, facts, out)
        out.append("## End to end: materialized (pipeline=device) and fused (pipeline=fused), measured spans")
        out.append("")
        e2e_table(rows, out)
        verdict(rows, out)
    print("\n".join(out))


if __name__ == "__main__":
    main(sys.argv)
