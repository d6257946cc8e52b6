#!/usr/bin/env python3
"""MLHCC's key kernel's L1: the modeled replay (bench/mlhcc_walks.cpp --l1) as tables, and the same counters read
from an Nsight Compute log of the pass (results/model/stage-counters/mlhcc-key-l1.md says how they test the stage
model's hypothesis for sibenik's key).

Usage:
  scripts/mlhcc_key_l1.py table L1.csv
      The modeled figures per warp (MODELED) of every row of `raycoh_mlhcc_walks --l1` output, sibenik beside the
      other scenes, and sibenik's row as the counters Nsight Compute reports.
  scripts/mlhcc_key_l1.py measured LOG...
      Per log (`OUT/ncu-stage-noopt_mlhcc*.log` of `scripts/gpu-check run OUT --stages`), the same counters of its
      last key_kernel launch (the timed pass) per warp (MEASURED).
"""
import csv
import math
import os
import sys

import stage_counters as sc

LD = "l1tex__t_sectors_pipe_lsu_mem_global_op_ld"
REQUESTS = "l1tex__t_requests_pipe_lsu_mem_global_op_ld.sum"


def f(r, k):
    return float(r[k])


def walk(r):
    return f(r, "node_misses") + f(r, "cut_misses")


def table(path):
    with open(path, newline="") as fh:
        rows = list(csv.DictReader(fh))
    print("| resident blocks | scene | requests | sectors | L1 misses (ray + node + cut) | L1 hit % | misses, pending "
          "as miss | hit %, pending as miss | node-miss steps | L2 bytes | DRAM sectors |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['resident_blocks']} | {r['scene']} | {f(r, 'requests'):.1f} | {f(r, 'sectors'):.0f} | "
              f"{f(r, 'l1_misses'):.1f} ({f(r, 'ray_misses'):.1f} + {f(r, 'node_misses'):.1f} + "
              f"{f(r, 'cut_misses'):.1f}) | {r['l1_hit_pct']} | {f(r, 'l1_misses') + f(r, 'pending_hits'):.1f} | "
              f"{r['l1_hit_pct_pending_miss']} | {f(r, 'node_miss_steps'):.2f} | {f(r, 'l2_bytes'):.0f} | "
              f"{f(r, 'dram_sectors'):.1f} |")
    six = {r["scene"]: r for r in rows if r["resident_blocks"] == "6"}
    s = six["sibenik"]
    print()
    for o in ("conference", "country_kitchen"):
        r = six[o]
        pending = (f(s, "l1_misses") + f(s, "pending_hits")) / (f(r, "l1_misses") + f(r, "pending_hits"))
        print(f"- sibenik / {o} (6 resident blocks): sectors {f(s, 'sectors') / f(r, 'sectors'):.2f}x, L1 misses "
              f"{f(s, 'l1_misses') / f(r, 'l1_misses'):.2f}x (the walks' node + cut misses {walk(s) / walk(r):.2f}x), "
              f"misses with pending as miss {pending:.2f}x, L1 hit {f(s, 'l1_hit_pct') - f(r, 'l1_hit_pct'):+.2f} "
              "points")
    print("\n| counter (per warp of the key launch) | MODELED, sibenik, 6 resident blocks |\n|---|---|")
    print(f"| `{REQUESTS}` | {f(s, 'requests'):.1f} |")
    print(f"| `{LD}.sum` | {f(s, 'sectors'):.0f} |")
    print(f"| `{LD}_lookup_miss.sum` | {f(s, 'l1_misses'):.1f} ({f(s, 'l1_misses') + f(s, 'pending_hits'):.1f} with "
          "pending lookups as misses, at least) |")
    print(f"| load hit % = 1 − lookup_miss / sectors | {s['l1_hit_pct']} ({s['l1_hit_pct_pending_miss']}) |")
    print("| `l1tex__t_sector_hit_rate.pct` | ≈ the load hit % (beside the store's 4 sectors a warp) |")
    print(f"| `lts__t_bytes.sum` | {f(s, 'l2_bytes'):.0f} + 128 of the keys' stores = {f(s, 'l2_bytes') + 128:.0f} |")
    print(f"| `dram__bytes_read.sum` | {f(s, 'dram_sectors'):.1f} sectors = {f(s, 'dram_sectors') * 32:.0f} bytes |")


def measured(paths):
    print("| log | requests | sectors | lookup misses | load hit % | L1 sector hit % | L2 bytes | DRAM bytes read |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|")
    for path in paths:
        keys = [k for k in sc.read_log(path) if "key_kernel" in k["name"]]
        if not keys:
            print(f"| {os.path.basename(path)} | no key_kernel launch | | | | | | |")
            continue
        k = keys[-1]  # the timed pass's
        w = sc.measured(k)["warps"]
        m = k["metrics"]
        get = lambda name: m.get(name, math.nan) / w  # noqa: E731
        hit = 100 * (1 - m.get(LD + "_lookup_miss.sum", math.nan) / m.get(LD + ".sum", math.nan))
        print(f"| {os.path.basename(path)} | {sc.fmt(get(REQUESTS), 1)} | {sc.fmt(get(LD + '.sum'))} | "
              f"{sc.fmt(get(LD + '_lookup_miss.sum'), 1)} | {sc.fmt(hit, 2)} | "
              f"{sc.fmt(m.get('l1tex__t_sector_hit_rate.pct', math.nan), 2)} | {sc.fmt(get('lts__t_bytes.sum'))} | "
              f"{sc.fmt(get('dram__bytes_read.sum'))} |")


def main(argv):
    if len(argv) < 2 or argv[0] not in ("table", "measured") or (argv[0] == "table" and len(argv) != 2):
        print("usage: scripts/mlhcc_key_l1.py table L1.csv | measured LOG...", file=sys.stderr)
        return 2
    for path in argv[1:]:
        if not os.path.isfile(path):
            print(f"mlhcc_key_l1.py: {path}: no such file", file=sys.stderr)
            return 2
    table(argv[1]) if argv[0] == "table" else measured(argv[1:])
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
