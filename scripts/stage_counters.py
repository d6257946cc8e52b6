#!/usr/bin/env python3
"""Each device stage kernel's make-up, modeled beside Nsight Compute's counters: where the stage model's misses lie.

The stage model (simt/stage_model.h) prices a kernel by the largest of its terms: bytes, issue (partition cycles
per warp), L1 wavefronts and a latency term (a block's dependent chain, times the waves its occupancy allows). When
a stage misses, the time alone cannot say which part is wrong: the count of instructions, the occupancy, the
chain's latencies or a term the model lacks. This sets each part beside the counter that measures it.

Usage:
  scripts/stage_counters.py --metrics
      The --metrics list scripts/gpu-check passes to ncu (with the sections SpeedOfLight, Occupancy, LaunchStats and
      WarpStateStats) on the stage kernels.
  scripts/stage_counters.py predict [--model BIN] [--preset h200] [--gbuffer wide64|fields60] --mlhcc-walks CSV
      TABLE.csv... > prediction.csv
      The model with the trip-counted paths and the latency term (as `scripts/stage_model_check.py predict
      --trip-counts --noopt-path --latency`) of every pass of the tables, kernel by kernel (raycoh_stage_model
      --per-warp): warps, partition cycles per warp, bytes per warp, L1 wavefronts per warp (the generator),
      resident warps per SM and a block's chain (SM cycles), for the generator, key and gather kernels. MODELED;
      no time is read.
  scripts/stage_counters.py compare PREDICTION.csv [--scene S] LOG[@FIRST-LAST]=METHOD...
      Each profiled kernel (the last launch of each in the log: the timed pass; @FIRST-LAST: among those launches,
      numbered from 0 as ncu numbers them) beside its modeled make-up.
      LOG: an ncu --csv log (--page raw, or the section layout of results/stages/h200-6ebd003/ncu-stages.log.xz;
      .xz read too) of one method's pass; METHOD its method label as in PREDICTION.csv (e.g. noopt, ours,
      ours:tile=32x8,k=8, noopt+mlhcc). MEASURED and MODELED stand side by side, never combined.

What is measured, per kernel (Nsight Compute):
  instructions per warp   smsp__inst_executed.sum / warps; in the section layout (no such counter) derived as SM
                          active cycles x achieved active warps per SM x SMs / warp cycles per issued instruction /
                          warps, and marked "derived"
  cycles per instruction  warp cycles per issued instruction (smsp__average_warp_latency_per_inst_issued.ratio)
  warp lifetime           cycles per instruction x instructions per warp: the SM cycles a warp is resident, which
                          the latency term models as a block's chain
  resident warps per SM   theoretical (the occupancy limits) and achieved
  elapsed cycles          beside warps a SM / achieved warps x warp lifetime: the latency term's form (waves of
                          resident warps, each living its lifetime), checked on the measured figures alone (raw
                          layout only: with derived instructions it is the SM active cycles by construction)
  L1 wavefronts per warp  l1tex__data_pipe_lsu_wavefronts.sum / warps (raw layout only); L1 hit rate; L1/TEX %
  bytes per warp          dram__bytes_read.sum + dram__bytes_write.sum, and lts__t_bytes.sum, / warps (raw layout
                          only), beside the model's
                          bytes term (the traffic it prices at the streaming bandwidth)
  stalls                  the reasons of the warp state statistics, cycles per issued instruction (raw layout: every
                          reason over 1 cycle; section layout: the one the profiler's rule names)
"""
import argparse
import csv
import io
import lzma
import math
import os
import re
import subprocess
import sys

import stage_model_check as smc

SECTIONS = ("SpeedOfLight", "Occupancy", "LaunchStats", "WarpStateStats")
METRICS = ("smsp__inst_executed.sum", "l1tex__data_pipe_lsu_wavefronts.sum",
           "l1tex__data_pipe_lsu_wavefronts_mem_shared.sum", "l1tex__t_requests_pipe_lsu_mem_global_op_ld.sum",
           "l1tex__t_sectors_pipe_lsu_mem_global_op_ld.sum", "l1tex__t_sectors_pipe_lsu_mem_global_op_ld_lookup_miss.sum",
           "l1tex__t_sectors_pipe_lsu_mem_global_op_st.sum", "l1tex__f_wavefronts.sum", "l1tex__data_bank_writes.sum",
           "l1tex__lsuin_requests.sum", "l1tex__t_sector_hit_rate.pct", "lts__t_sector_hit_rate.pct",
           "lts__t_bytes.sum", "dram__bytes_read.sum", "dram__bytes_write.sum",
           "l1tex__throughput.avg.pct_of_peak_sustained_active",
           "smsp__issue_active.avg.pct_of_peak_sustained_active")

# The kernels the stage model prices (cuda/): the name a launch carries -> the model's kernel.
KERNELS = (("tile_hits", "tile_hits"), ("noopt_kernel", "gen"), ("group_kernel", "gen"), ("key_kernel", "key"),
           ("gather_batch", "gather"))

# (raw metric, section-layout name) of each measured figure.
FIGURES = {
    "inst": ("smsp__inst_executed.sum", None),
    "cpi": ("smsp__average_warp_latency_per_inst_issued.ratio", "Warp Cycles Per Issued Instruction"),
    "active_cycles": ("sm__cycles_active.avg", "SM Active Cycles"),
    "achieved": ("sm__warps_active.avg.per_cycle_active", "Achieved Active Warps Per SM"),
    "theoretical": ("sm__maximum_warps_per_active_cycle_pct", "Theoretical Active Warps per SM"),
    "sms": ("device__attribute_multiprocessor_count", "# SMs"),
    "elapsed": ("gpc__cycles_elapsed.max", "Elapsed Cycles"),
    "l1_wavefronts": ("l1tex__data_pipe_lsu_wavefronts.sum", None),
    "l1_hit": ("l1tex__t_sector_hit_rate.pct", "L1/TEX Hit Rate"),
    "l1_pct": ("l1tex__throughput.avg.pct_of_peak_sustained_active", "L1/TEX Cache Throughput"),
    "dram_read": ("dram__bytes_read.sum", None),
    "dram_write": ("dram__bytes_write.sum", None),
    "l2_bytes": ("lts__t_bytes.sum", None),
}
STALL = re.compile(r"smsp__average_warps_issue_stalled_(\w+)_per_issue_active\.ratio")
RULE_STALL = re.compile(r"spends ([\d.]+) cycles being stalled (.+?)\. ")


def number(text):
    try:
        return float(str(text).replace(",", ""))
    except ValueError:
        return math.nan


def read_log(path):
    """The launches of an ncu --csv log in launch order: {"name", "block", "grid", "metrics", "rules"}."""
    with (lzma.open if path.endswith(".xz") else open)(path, "rt", errors="replace") as f:
        lines = [line for line in f.read().splitlines() if line.startswith('"')]
    launches = {}
    for row in csv.DictReader(io.StringIO("\n".join(lines))):
        if not (row.get("ID") or "").isdigit():
            continue  # the raw layout's units row
        k = launches.setdefault(row["ID"], {"name": row["Kernel Name"], "block": row.get("Block Size", ""),
                                            "grid": row.get("Grid Size", ""), "metrics": {}, "rules": []})
        if "Metric Name" in row:  # the section layout: one metric (or one rule) a line
            if row["Metric Name"]:
                k["metrics"][row["Metric Name"]] = number(row["Metric Value"])
            elif row.get("Rule Description"):
                k["rules"].append(row["Rule Description"])
        else:
            k["metrics"].update({m: number(v) for m, v in row.items() if "__" in m})
    return [launches[i] for i in sorted(launches, key=int)]


def dims(text):
    return [int(x) for x in re.findall(r"\d+", text or "")] or [0]


def figure(k, name):
    raw, section = FIGURES[name]
    m = k["metrics"]
    if raw in m:
        v = m[raw]
        return v * 64 / 100 if name == "theoretical" else v  # a percentage of sm_90's 64 warps
    return m.get(section, math.nan) if section else math.nan


def measured(k):
    """The measured make-up of launch k (NaN where the log lacks a counter)."""
    b, g = dims(k["block"]), dims(k["grid"])
    warps = math.prod(g) * math.ceil(math.prod(b) / 32)
    inst, derived = figure(k, "inst"), False
    if math.isnan(inst):
        inst = figure(k, "active_cycles") * figure(k, "achieved") * figure(k, "sms") / figure(k, "cpi")
        derived = True
    per_warp = inst / warps if warps else math.nan
    reasons = {s.group(1): v for m, v in k["metrics"].items()
               if (s := STALL.fullmatch(m)) and "not_issued" not in m and not math.isnan(v)}
    cpi = figure(k, "cpi")
    if math.isnan(cpi) and reasons:
        cpi = sum(reasons.values())  # the reasons of every issue slot add up to the warp cycles per issue
    stalls = {r: v for r, v in reasons.items() if v >= 1.0}
    for rule in k["rules"]:
        s = RULE_STALL.search(rule)
        if s:
            stalls[s.group(2)] = float(s.group(1))
    return {"warps": warps, "inst": per_warp, "derived": derived, "cpi": cpi, "lifetime": cpi * per_warp,
            # derived instructions make this the SM active cycles by construction: no check, not shown
            "waves_lifetime": math.nan if derived or not warps else warps / figure(k, "sms") / figure(k, "achieved") *
            cpi * per_warp,
            "elapsed": figure(k, "elapsed"), "theoretical": figure(k, "theoretical"),
            "achieved": figure(k, "achieved"), "l1_wavefronts": figure(k, "l1_wavefronts") / warps if warps else
            math.nan, "l1_hit": figure(k, "l1_hit"), "l1_pct": figure(k, "l1_pct"),
            "dram": (figure(k, "dram_read") + figure(k, "dram_write")) / warps if warps else math.nan,
            "l2_bytes": figure(k, "l2_bytes") / warps if warps else math.nan, "stalls": stalls}


def kernel_of(name):
    for key, kernel in KERNELS:
        if key in name:
            return kernel
    return None


def predict(args):
    rows = smc.read_passes(args.tables)
    with open(args.mlhcc_walks, newline="") as f:
        walks = {w["scene"]: (w["origin_trips"], w["end_trips"]) for w in csv.DictReader(f)}
    lobes = smc.scene_groups(rows)
    lines = [smc.describe(r, args.preset, str(i), args.gbuffer, True, walks, lobes, True) for i, r in enumerate(rows)]
    out = subprocess.run([smc.model_binary(args.model), "--per-warp"], input="\n".join(lines) + "\n",
                         capture_output=True, text=True, check=True).stdout
    modeled = {m["label"]: m for m in csv.DictReader(out.splitlines())}
    w = csv.writer(sys.stdout, lineterminator="\n")
    w.writerow(["kind", "preset", "gbuffer", "file", "scene", "method", "kernel", "warps", "cycles_per_warp",
                "bytes_per_warp", "l1_wavefronts_per_warp", "resident_warps", "chain_cycles"])
    seen = set()
    for i, r in enumerate(rows):
        m, key = modeled[str(i)], (r["scene"], smc.method_label(r))
        if key in seen:
            continue  # a method in two tables (noopt): the same pass
        seen.add(key)
        lead = ["modeled", args.preset, args.gbuffer, r["_file"], r["scene"], smc.method_label(r)]
        for kernel in ("gen", "key", "gather"):
            warps = float(m[f"{kernel}_warps"])
            if warps > 0:
                w.writerow(lead + [kernel, m[f"{kernel}_warps"], m[f"{kernel}_cycles_per_warp"],
                                   f"{float(m[f'{kernel}_bytes']) / warps:.1f}",
                                   m["gen_l1_wavefronts"] if kernel == "gen" else "",
                                   m[f"{kernel}_resident_warps"], m[f"{kernel}_chain_cycles"]])


def fmt(v, digits=0):
    return "—" if v is None or (isinstance(v, float) and math.isnan(v)) else f"{v:,.{digits}f}"


def ratio(a, b):
    return fmt(a / b, 2) if a and b and not (math.isnan(a) or math.isnan(b)) else "—"


def compare(args):
    with open(args.prediction, newline="") as f:
        modeled = {(r["scene"], r["method"], r["kernel"]): r for r in csv.DictReader(f)}
    print("## Stage kernels: measured (Nsight Compute) beside modeled (simt stage model)\n")
    print("Measured: the last launch of each kernel in each log (the timed pass; SM cycles at the profiler's clock). "
          "Modeled: the prediction's make-up of the same pass. Each pair stands side by side, never combined; "
          "modeled / measured after each.\n")
    print("| method | kernel | instructions / warp, measured | modeled (partition cycles) | ratio | "
          "cycles / instruction, measured | warp lifetime, measured | block chain, modeled | ratio | "
          "resident warps / SM, measured (theoretical, achieved) | modeled | L1 wavefronts / warp, measured | "
          "modeled | L1 hit % | L1/TEX % | elapsed cycles, measured | warps a SM ÷ achieved × lifetime |")
    print("|---|---|---:|---:|---:|---:|---:|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|")
    notes, traffic = [], []
    for item in args.logs:
        path, _, method = item.partition("=")
        path, _, span = path.partition("@")
        first, _, end = span.partition("-")
        last = {}
        for i, k in enumerate(read_log(path)):
            kernel = kernel_of(k["name"])
            if kernel and (not span or int(first) <= i <= int(end or first)):
                last[kernel] = k
        for kernel, k in last.items():
            x = measured(k)
            p = modeled.get((args.scene, method, kernel), {})
            mc, ml = number(p.get("cycles_per_warp", "nan")), number(p.get("l1_wavefronts_per_warp", "nan"))
            chain, res = number(p.get("chain_cycles", "nan")), number(p.get("resident_warps", "nan"))
            inst = fmt(x["inst"]) + (" (derived)" if x["derived"] else "")
            print(f"| {method} | {kernel} | {inst} | {fmt(mc)} | {ratio(mc, x['inst'])} | {fmt(x['cpi'], 1)} | "
                  f"{fmt(x['lifetime'])} | {fmt(chain)} | {ratio(chain, x['lifetime'])} | "
                  f"{fmt(x['theoretical'])}, {fmt(x['achieved'], 1)} | {fmt(res)} | {fmt(x['l1_wavefronts'], 1)} | "
                  f"{fmt(ml, 1)} | {fmt(x['l1_hit'], 1)} | {fmt(x['l1_pct'], 1)} | {fmt(x['elapsed'])} | "
                  f"{fmt(x['waves_lifetime'])} |")
            mb = number(p.get("bytes_per_warp", "nan"))
            if not (math.isnan(x["dram"]) and math.isnan(x["l2_bytes"])):
                traffic.append(f"| {method} | {kernel} | {fmt(x['dram'])} | {fmt(x['l2_bytes'])} | {fmt(mb)} | "
                               f"{ratio(mb, x['dram'])} |")
            if x["stalls"]:
                top = sorted(x["stalls"].items(), key=lambda s: -s[1])[:4]
                notes.append(f"- {method}, {kernel}: " + "; ".join(f"{r} {v:.1f}" for r, v in top) +
                             f" (of {fmt(x['cpi'], 1)} cycles per issued instruction)")
    print("\nBytes per warp: DRAM (read and written) and L2 traffic (measured) beside the bytes the model's bytes "
          "term prices (modeled):\n")
    print("| method | kernel | DRAM, measured | L2, measured | modeled | modeled / DRAM |")
    print("|---|---|---:|---:|---:|---:|")
    print("\n".join(traffic) if traffic else "| — | | | | | |")
    if notes:
        print("\nStalls, cycles per issued instruction by reason (measured):\n")
        print("\n".join(notes))


def main(argv):
    if argv == ["--metrics"]:
        print(",".join(METRICS))
        return 0
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    sub = p.add_subparsers(dest="command", required=True)
    pr = sub.add_parser("predict")
    pr.add_argument("--model")
    pr.add_argument("--preset", default="h200")
    pr.add_argument("--gbuffer", default="wide64", choices=("wide64", "fields60"))
    pr.add_argument("--mlhcc-walks", required=True)
    pr.add_argument("tables", nargs="+")
    co = sub.add_parser("compare")
    co.add_argument("--scene", default="sibenik")
    co.add_argument("prediction")
    co.add_argument("logs", nargs="+", metavar="LOG=METHOD")
    args = p.parse_args(argv)
    for item in getattr(args, "logs", []):
        if "=" not in item:
            p.error(f"{item}: give each log as LOG=METHOD (its method label in the prediction, e.g. noopt+mlhcc)")
        span = item.partition("=")[0].partition("@")[2]
        if span and not re.fullmatch(r"\d+(-\d+)?", span):
            p.error(f"{item}: @{span}: give the launches as @FIRST-LAST (ncu's launch numbers, e.g. @0-3)")
    paths = {"compare": lambda: [args.prediction] + [i.partition("=")[0].partition("@")[0] for i in args.logs],
             "predict": lambda: list(args.tables) + [args.mlhcc_walks]}[args.command]()
    for path in paths:
        if not os.path.isfile(path):
            p.error(f"{path}: no such file")
    predict(args) if args.command == "predict" else compare(args)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
