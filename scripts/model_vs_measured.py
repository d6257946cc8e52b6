#!/usr/bin/env python3
"""Measured trace-kernel times (the `cuda` rows of GPU runs) beside MODELED ones (the `simt` rows of other runs of
the same scenes, methods and resolution): one markdown row per scene, method and BVH layout.

Usage: model_vs_measured.py --measured A.csv [B.csv ...] --modeled C.csv [D.csv ...] [--before E.csv ...]
  --measured  table CSVs of a GPU run; rows of tracer `cuda` (not counters=on), first row of each key wins
  --modeled   table CSVs with `simt` rows: the model as it is now
  --before    table CSVs with `simt` rows of an earlier model (e.g. the GPU run's own simt rows), BVH2 only
Columns: measured ms; the earlier and the current modeled ms and their ratio to the measured; the modeled limiter;
the speed ratio to noopt, measured and modeled now.
"""
import argparse
import csv

from result_key import row_layout, tracer_parameters


def rows_of(paths, tracer):
    out = {}
    for path in paths:
        for r in csv.DictReader(open(path)):
            if r["tracer"] != tracer or tracer_parameters(r).get("counters") == "on" or r.get("run_under"):
                continue
            out.setdefault((r["scene"], r["method"], row_layout(r)), r)
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--measured", nargs="+", required=True)
    ap.add_argument("--modeled", nargs="+", required=True)
    ap.add_argument("--before", nargs="*", default=[])
    a = ap.parse_args()
    measured = {k: float(r["trace_ms"]) for k, r in rows_of(a.measured, "cuda").items()}
    modeled = rows_of(a.modeled, "simt")
    before = {k: float(r["modeled_ms"]) for k, r in rows_of(a.before, "simt").items()}
    print("| scene | method | BVH | measured ms | MODELED before | ÷ measured | MODELED now | ÷ measured | limiter "
          "| ×noopt measured | ×noopt MODELED now |")
    print("|---|---|---|---:|---:|---:|---:|---:|---|---:|---:|")
    for key, r in modeled.items():
        if key not in measured:
            continue
        now, m = float(r["modeled_ms"]), measured[key]
        base = (key[0], "noopt", key[2])
        b = before.get(key)
        b_text = f"{b:.3f} | {b / m:.2f}" if b else "– | –"
        ratio_m = measured[base] / m if base in measured else float("nan")
        ratio_n = float(modeled[base]["modeled_ms"]) / now if base in modeled else float("nan")
        print(f"| {key[0]} | {key[1]} | {key[2]} | {m:.3f} | {b_text} | {now:.3f} | {now / m:.2f} | "
              f"{r['modeled_limiter']} | {ratio_m:.3f} | {ratio_n:.3f} |")


if __name__ == "__main__":
    main()
