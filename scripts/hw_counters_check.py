#!/usr/bin/env python3
"""cuda:counters=hw (CUPTI's range profiler in raycoh) against Nsight Compute on the same kernels and batches.

Usage:
  scripts/hw_counters_check.py --metrics
      the Nsight Compute metric list the mode reads, comma-separated (what scripts/gpu-check passes to ncu --metrics)
  scripts/hw_counters_check.py --modeled-table PRED.csv
      the prediction's modeled counters per method, alone (results/model/hw-counters/prediction.md)
  scripts/hw_counters_check.py HW.csv NCU.log [NCU.log ...] [--tolerance 0.02] [--modeled PRED.csv] [--more ALL.csv]
      HW.csv: a `raycoh table` CSV with cuda:counters=hw rows (sibenik, noopt and ours, bvh2 and cwbvh kernels);
      NCU.log: `ncu --csv --page raw --metrics $(--metrics) --kernel-name regex:persistent_kernel --launch-count 6`
      of the same table without the mode (--repeat 1, so launches 2k and 2k+1 are row k's warm-up and timed pass:
      primary, noopt, ours), named hw-ncu-<bvh2|cwbvh>-<cache control>.log by scripts/gpu-check --hw-counters.
      Prints, per log, each counter of each kernel measured both ways and its relative difference, then whether every
      counter is within the tolerance (the issue's goal: 2%), per ncu cache-control setting over both kernels; exits 1
      when no setting meets it. Where the CSV also holds
      simt rows, a modeled-vs-measured table follows (L1 wavefronts, hit rates, DRAM bytes per ray).
      --modeled PRED.csv: the simt rows of that table from a committed prediction (a `raycoh table --tracers simt:...`
      CSV made before the measurement, e.g. results/model/hw-counters/prediction.csv) instead of HW.csv's;
      --more ALL.csv: cuda:counters=hw rows of more methods (every method of the comparison table) for that table
      only; the ncu comparison reads HW.csv's alone.

Both sides are measured on the GPU; nothing here is modeled except the simt columns of the last table. The mapping
below must name the same metrics as tracers/hw_counters.cpp (tests/hw_counters_test.cpp checks that it does).
"""
import csv
import math
import os
import re
import sys

from result_key import row_layout

# column -> (metrics summed, per ray?)
METRICS = {
    "hw_l1_hit_pct": (["l1tex__t_sector_hit_rate.pct"], False),
    "hw_l2_hit_pct": (["lts__t_sector_hit_rate.pct"], False),
    "hw_l1_wavefronts_per_ray": (["l1tex__data_pipe_lsu_wavefronts.sum"], True),
    "hw_l1_tag_wavefronts_per_ray": (["l1tex__t_output_wavefronts_pipe_lsu_mem_global_op_ld.sum"], True),
    "hw_l2_bytes_per_ray": (["lts__t_bytes.sum"], True),
    "hw_dram_bytes_per_ray": (["dram__bytes_read.sum"], True),
    "hw_local_requests_per_ray": (["l1tex__t_requests_pipe_lsu_mem_local_op_ld.sum",
                                   "l1tex__t_requests_pipe_lsu_mem_local_op_st.sum"], True),
    "hw_inst_per_ray": (["smsp__inst_executed.sum"], True),
    "hw_issue_pct": (["smsp__issue_active.avg.pct_of_peak_sustained_active"], False),
    "hw_l1_util_pct": (["l1tex__throughput.avg.pct_of_peak_sustained_active"], False),
    "hw_occupancy_pct": (["sm__warps_active.avg.pct_of_peak_sustained_active"], False),
}
ROWS = ["primary", "noopt", "ours"]  # the table's row order, one pair of ncu launches each


def metric_names():
    names = []
    for metrics, _ in METRICS.values():
        names.extend(m for m in metrics if m not in names)
    return names


def number(text):
    try:
        return float(text.replace(",", ""))
    except ValueError:
        return math.nan


def read_ncu(path):
    """The kernels of an ncu --csv --page raw log, in launch order: metric -> value."""
    kernels, header = [], None
    with open(path, newline="") as f:
        for line in f:
            if header is None:
                if line.startswith('"ID"'):
                    header = next(csv.reader([line]))
                continue
            fields = next(csv.reader([line]), [])
            if len(fields) != len(header) or not fields[0].isdigit():
                continue  # the units row, or a line of the program's own output
            kernels.append({h: number(v) for h, v in zip(header, fields)})
    return kernels


def read_hw(path):
    """(layout, method) -> row of the cuda:counters=hw rows; and the simt rows by method."""
    hw, simt = {}, {}
    with open(path, newline="") as f:
        for r in csv.DictReader(f):
            if r["tracer"] == "simt":
                simt[r["method"]] = r
            elif r["tracer"] == "cuda" and r.get("run_under") == "cupti-counters":
                hw[(row_layout(r), r["method"])] = r
    return hw, simt


def counters_not_read(path, hw):
    """Why the CSV's cuda:counters=hw rows hold no counters ("" when some do): the mode said so in one line (the
    table's log) and ran them as ordinary timings. Under GPGPU-Sim (the rows' device column) that is expected."""
    if hw:
        return ""
    with open(path, newline="") as f:
        rows = [r for r in csv.DictReader(f) if r["tracer"] == "cuda" and "counters=hw" in r.get("tracer_params", "")]
    if any(r.get("device", "").startswith("simulated") for r in rows):
        return ("simulated device (GPGPU-Sim): no hardware counters, nothing to compare (expected in a dry run; "
                "the hw_* columns are empty)")
    return ("NO COUNTERS READ: the cuda:counters=hw rows ran as ordinary timings (the mode's one line in the table's "
            "log says why: no device, CUPTI not loaded, or profiling restricted); nothing to compare")


def hw_value(row, column, per_ray):
    text = row.get(column, "")
    if not text:
        return math.nan
    return float(text) * float(row["rays"]) if per_ray else float(text)


def ncu_value(kernel, metrics):
    values = [kernel.get(m, math.nan) for m in metrics]
    return sum(values)


def rel(a, b):
    if math.isnan(a) or math.isnan(b):
        return math.nan
    if a == b:
        return 0.0
    return abs(a - b) / max(abs(b), 1e-12)


def compare_log(path, hw, tolerance):
    name = os.path.basename(path)
    m = re.match(r"hw-ncu-(bvh2|cwbvh)-(\w+)\.log", name)
    layout, cache = (m.group(1), m.group(2)) if m else ("bvh2", "?")
    kernels = read_ncu(path)
    print(f"\n## {name}: {layout} kernel, ncu --cache-control {cache}, {len(kernels)} launches\n")
    print("| row | counter | counters=hw | Nsight Compute | difference |\n|---|---|---:|---:|---:|")
    worst, missing = 0.0, 0
    for k, method in enumerate(ROWS):
        row = hw.get((layout, method))
        if row is None or 2 * k + 1 >= len(kernels):
            print(f"| {method} | (missing: {'no counters=hw row' if row is None else 'no ncu launch'}) | | | |")
            missing += 1
            continue
        kernel = kernels[2 * k + 1]  # the timed pass of the row
        for column, (metrics, per_ray) in METRICS.items():
            a, b = hw_value(row, column, per_ray), ncu_value(kernel, metrics)
            d = rel(a, b)
            if math.isnan(d):
                missing += 1
            else:
                worst = max(worst, d)
            print(f"| {method} | {column} | {a:.6g} | {b:.6g} | {'—' if math.isnan(d) else f'{100 * d:.2f}%'} |")
    ok = missing == 0 and worst <= tolerance
    print(f"\n{name}: worst difference {100 * worst:.2f}%, {missing} missing; "
          f"{'every counter within' if ok else 'NOT every counter within'} {100 * tolerance:.0f}%")
    return cache, ok


def modeled_figures(s):
    """A simt row's L1 wavefronts, L1 and L2 hit % (of the BVH fetches) and DRAM bytes, per ray: MODELED."""
    f = lambda c: float(s[c]) if s.get(c) else math.nan  # noqa: E731
    fetches, l1m, l2m = f("fetches_per_ray"), f("l1_misses_per_ray"), f("l2_misses_per_ray")
    l1_hit = 100 * (1 - l1m / fetches) if fetches > 0 else math.nan
    l2_hit = 100 * (1 - l2m / l1m) if l1m > 0 else math.nan
    return f("modeled_l1_wavefronts_per_ray"), l1_hit, l2_hit, f("dram_bytes_per_ray")


def modeled_table(path):
    """--modeled-table PRED.csv: the prediction's figures alone, per method (what a later run is compared with)."""
    simt = read_hw(path)[1]
    if not simt:
        print(f"hw_counters_check.py: {path}: no simt rows", file=sys.stderr)
        return 2
    first = next(iter(simt.values()))
    print(f"# MODELED counters per ray (simt, {first.get('tracer_params', '').split(',')[0]}; {first.get('scene')} "
          f"{first.get('width')}x{first.get('height')}, frame {first.get('frame')}, seed {first.get('seed')}; "
          f"{path})\n")
    print("| method | L1 wavefronts | L1 hit % | L2 hit % | DRAM bytes |\n|---|---:|---:|---:|---:|")
    for method, s in simt.items():
        l1w, l1_hit, l2_hit, dram = modeled_figures(s)
        print(f"| {method} | {l1w:.1f} | {l1_hit:.1f} | {l2_hit:.1f} | {dram:.1f} |")
    print("\n(hit rates and DRAM bytes of the BVH fetches only: the model has no other access of the kernel)")
    return 0


def modeled_vs_measured(hw, simt, source):
    if not simt:
        return
    print(f"\n## MODELED (simt, {source}) vs MEASURED (cuda:counters=hw, BVH2 kernel), per ray\n")
    print("| method | L1 wavefronts modeled / measured | L1 hit % modeled / measured | "
          "L2 hit % modeled / measured | DRAM bytes modeled / measured |\n|---|---:|---:|---:|---:|")
    for method, s in simt.items():
        h = hw.get(("bvh2", method))
        if h is None:
            continue
        f = lambda r, c: float(r[c]) if r.get(c) else math.nan  # noqa: E731
        l1w, l1_hit, l2_hit, dram = modeled_figures(s)
        print(f"| {method} | {l1w:.1f} / {f(h, 'hw_l1_wavefronts_per_ray'):.1f} | "
              f"{l1_hit:.1f} / {f(h, 'hw_l1_hit_pct'):.1f} | {l2_hit:.1f} / {f(h, 'hw_l2_hit_pct'):.1f} | "
              f"{dram:.1f} / {f(h, 'hw_dram_bytes_per_ray'):.1f} |")
    unmeasured = [m for m in simt if ("bvh2", m) not in hw]
    if unmeasured:
        print(f"\nModeled but not measured (no cuda:counters=hw row): {', '.join(unmeasured)}")
    print("\n(the model's hit rates and DRAM bytes count BVH fetches only; the GPU's count every access of the "
          "kernel: rays, hits and the stack too)")


def main(argv):
    if argv[1:] == ["--metrics"]:
        print(",".join(metric_names()))
        return 0
    if len(argv) == 3 and argv[1] == "--modeled-table":
        return modeled_table(argv[2])
    args, tolerance, modeled, more = [], 0.02, None, None
    i = 1
    while i < len(argv):
        if argv[i] in ("--tolerance", "--modeled", "--more") and i + 1 < len(argv):
            if argv[i] == "--tolerance":
                tolerance = float(argv[i + 1])
            elif not os.path.isfile(argv[i + 1]):
                print(f"hw_counters_check.py: {argv[i]} {argv[i + 1]}: no such file", file=sys.stderr)
                return 2
            elif argv[i] == "--modeled":
                modeled = argv[i + 1]
            else:
                more = argv[i + 1]
            i += 2
        else:
            args.append(argv[i])
            i += 1
    if len(args) < 2:
        print(__doc__, file=sys.stderr)
        return 2
    if not os.path.isfile(args[0]):
        print(f"# cuda:counters=hw vs Nsight Compute: no {args[0]} (the hw-counters table step failed: its log says why)")
        return 1
    hw, simt = read_hw(args[0])
    unread = counters_not_read(args[0], hw)
    if unread:
        print(f"# cuda:counters=hw vs Nsight Compute ({args[0]}): {unread}")
        return 0 if unread.startswith("simulated") else 1
    print(f"# cuda:counters=hw vs Nsight Compute ({args[0]}; both measured on the GPU)")
    by_cache = {}
    for path in args[1:]:
        if os.path.exists(path):
            cache, ok = compare_log(path, hw, tolerance)
            by_cache[cache] = by_cache.get(cache, True) and ok
    print("\n## Goal: every counter of every kernel within {:.0f}% of Nsight Compute\n".format(100 * tolerance))
    for cache, ok in by_cache.items():
        print(f"- ncu --cache-control {cache}: {'met' if ok else 'NOT met'}")
    if not by_cache:
        print("- no Nsight Compute log to compare with")
    table_hw = dict(hw)
    if more:
        for key, row in read_hw(more)[0].items():
            table_hw.setdefault(key, row)
    if modeled:
        simt = read_hw(modeled)[1]
    modeled_vs_measured(table_hw, simt, f"the prediction {modeled}" if modeled else f"the rows of {args[0]}")
    return 0 if any(by_cache.values()) else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv))
