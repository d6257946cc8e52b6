#!/usr/bin/env python3
"""The L1 probe's verdict (bench/l1_probe.cu, scripts/gpu-check --l1): for each candidate wavefront rule
(bench/l1_patterns.h), how well it predicts the measured L1 work of each lane pattern.

Usage: l1_probe_summary.py TIMED.csv [NCU_ORDER.csv NCU.log [NCU2_ORDER.csv NCU2.log MEASURED.csv]]
  TIMED.csv      raycoh_bench_l1 --out: cycles per warp load per pattern (clock64 per SM; a floor of issue and LSU
                 throughput sits under it)
  NCU_ORDER.csv  raycoh_bench_l1 --ncu --out: the patterns in launch order
  NCU.log        Nsight Compute's --csv --page raw output of that run: wavefronts and requests per launch
  NCU2_*         the run with the tag stage's counter (l1tex__t_output_wavefronts...); MEASURED.csv: written, one
                 row per pattern (offsets, timed cycles, data- and tag-stage wavefronts) for tests/l1_patterns_test.cpp
Prints, per rule, the patterns it predicts exactly (ncu wavefronts per request, rounded) and its mean absolute
error in wavefronts and in timed cycles; then every pattern with its features and both measurements.
"""
import csv
import io
import os
import sys

RULES = ["lines4", "lines", "sectors4", "bank_max", "gpgpusim", "bytes128"]


def read_rows(path):
    with open(path) as f:
        return list(csv.DictReader(line for line in f if not line.startswith("#")))


def ncu_launches(log_path):
    """Metric rows of an ncu --csv --page raw log, in launch order (the units row dropped)."""
    with open(log_path) as f:
        lines = [l for l in f if l.startswith('"')]
    if not lines:
        return []
    rows = list(csv.DictReader(io.StringIO("".join(lines))))
    return [r for r in rows if r.get("ID", "").strip().isdigit()]


def number(text):
    return float(text.replace(",", "")) if text not in (None, "", "n/a") else float("nan")


def iters_of(path):
    """The loop trips of a raycoh_bench_l1 run, from its CSV's first (comment) line: '... iters N, ...'."""
    with open(path) as f:
        words = f.readline().replace(",", " ").split()
    return int(words[words.index("iters") + 1])


def ncu_per_request(order_path, log_path):
    """pattern name -> (wavefronts per pattern load, sectors per request) from the ncu run."""
    order = read_rows(order_path)
    loads_per_warp = 8 * (iters_of(order_path) + 1) + 1  # the loop, the warm-up trip, the offsets load
    launches = ncu_launches(log_path)
    out = {}
    for pat, launch in zip(order, launches):
        requests = number(launch["l1tex__t_requests_pipe_lsu_mem_global_op_ld.sum"])
        waves = number(launch["l1tex__data_pipe_lsu_wavefronts.sum"])
        sectors = number(launch["l1tex__t_sectors_pipe_lsu_mem_global_op_ld.sum"])
        # per warp: 1 offsets load (one wavefront) and one sink store (one wavefront) besides the pattern's loads
        warps = requests / loads_per_warp
        pattern_loads = requests - warps
        ncu_requests[pat["pattern"]] = (pattern_loads, warps)  # the offsets load: one tag wavefront a warp
        out[pat["pattern"]] = ((waves - 2 * warps) / pattern_loads if pattern_loads else float("nan"),
                               sectors / requests if requests else float("nan"))
    return out


def write_measured(path, timed, ncu, order2, log2):
    """One row per pattern: what tests/l1_patterns_test.cpp checks the model's rule against."""
    tags = {}
    if order2 and os.path.exists(order2) and os.path.exists(log2):
        # the tag run has no request counter: its warps are the first run's (same grid, same iterations)
        for pat, launch in zip(read_rows(order2), ncu_launches(log2)):
            tags[pat["pattern"]] = number(launch["l1tex__t_output_wavefronts_pipe_lsu_mem_global_op_ld.sum"])
    with open(path, "w") as f:
        f.write("pattern,width,cycles_per_load,data_wavefronts,tag_wavefronts,offsets\n")
        for r in timed:
            name = r["pattern"]
            data = ncu.get(name, (float("nan"),))[0]
            tag = ""
            if name in tags:
                # per pattern load: the same warps and loads as the first ncu run (grid = SMs x 1 block of 256)
                first = ncu_requests.get(name)
                tag = f"{(tags[name] - first[1]) / first[0]:.3f}" if first else ""
            f.write(f"{name},{r['width']},{float(r['cycles_per_load']):.3f},{data:.3f},{tag},{r['offsets']}\n")


ncu_requests = {}


def main(argv):
    if len(argv) not in (2, 4, 7):
        sys.exit(__doc__)
    timed = read_rows(argv[1])
    have_ncu = len(argv) >= 4 and os.path.exists(argv[2]) and os.path.exists(argv[3])
    ncu = ncu_per_request(argv[2], argv[3]) if have_ncu else {}
    print(f"{'rule':10} {'exact (ncu)':>12} {'mean |err| wavefronts':>22} {'mean |err| cycles':>18}")
    for rule in RULES + ["max(bank_max,bytes128)"]:
        exact = n = 0
        err_w = err_c = 0.0
        for r in timed:
            pred = (max(int(r["bank_max"]), int(r["bytes128"])) if rule.startswith("max")
                    else int(r[rule]))
            err_c += abs(float(r["cycles_per_load"]) - pred)
            if r["pattern"] in ncu:
                w = ncu[r["pattern"]][0]
                n += 1
                exact += round(w) == pred
                err_w += abs(w - pred)
        ncu_text = f"{exact}/{n}" if n else "-"
        print(f"{rule:10} {ncu_text:>12} {err_w / n if n else float('nan'):>22.2f} {err_c / len(timed):>18.2f}")
    print()
    print(f"{'pattern':32} {'w':>2} {'lines':>5} {'sect':>4} {'bank':>4} {'gsim':>4} {'l/4':>3} "
          f"{'cycles':>7} {'ncu wf':>7} {'sect/req':>8}")
    for r in timed:
        w, spr = ncu.get(r["pattern"], (float("nan"), float("nan")))
        print(f"{r['pattern']:32} {r['width']:>2} {r['lines']:>5} {r['sectors']:>4} {r['bank_max']:>4} "
              f"{r['gpgpusim']:>4} {r['lines4']:>3} {float(r['cycles_per_load']):7.2f} {w:7.2f} {spr:8.2f}")


    if len(argv) == 7:
        write_measured(argv[6], timed, ncu, argv[4], argv[5])


if __name__ == "__main__":
    main(sys.argv)
