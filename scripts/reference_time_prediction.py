#!/usr/bin/env python3
"""The modeled time of a path-traced reference on a GPU, from `raycoh converge --gpu-model simt:preset=P` rows: per
method, the timing model's GPU milliseconds per frame (every batch the frame traces: camera rays, each bounce,
shadow rays, plus the modeled generation) and the rays per frame, the modeled trace rate, and that time over
--frames frames. MODELED, not measured: the model prices the trace kernels and generation only, so the figure is a
lower bound on the device path tracer's frame (its shading, sampling and gather kernels and the per-frame download
of the radiance are not in it) and the remainder that a time goal (--goal-s) leaves per frame for them is printed.

Usage: reference_time_prediction.py converge.csv [converge.csv ...] [--frames 4096] [--goal-s 300]
Standard library only.
"""
import argparse
import csv
import sys

NEEDED = ("method", "width", "height", "rays", "frame_modeled_gpu_ms", "frame_modeled_trace_ms", "gpu_model")


def read_rows(paths):
    rows = []
    for path in paths:
        with open(path, newline="") as f:
            reader = csv.DictReader(f)
            missing = [c for c in NEEDED if c not in (reader.fieldnames or [])]
            if missing:
                sys.exit(f"reference_time_prediction.py: {path}: no column {missing[0]} (a converge CSV with "
                         "--gpu-model is needed)")
            rows += [r for r in reader if r["frame_modeled_gpu_ms"] not in ("", "nan")]
    if not rows:
        sys.exit("reference_time_prediction.py: no modeled frames (run converge with --gpu-model simt:...)")
    return rows


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("csv", nargs="+")
    ap.add_argument("--frames", type=int, default=4096, help="frames of the reference (the paper's: 4096)")
    ap.add_argument("--goal-s", type=float, default=300.0, help="the time goal of the whole reference, seconds")
    a = ap.parse_args()
    rows = read_rows(a.csv)
    by_method = {}
    for r in rows:
        by_method.setdefault(r["method"], []).append(r)
    first = rows[0]
    print(f"MODELED ({first['gpu_model'].split(',')[0]}]; trace kernels and generation only), "
          f"{first['width']}x{first['height']}, {a.frames} frames, goal {a.goal_s:g} s:\n")
    print("| method | frames modeled | rays per frame (M) | modeled GPU ms per frame | modeled GRay/s | "
          f"modeled {a.frames} frames (s) | left per frame for the rest (ms) |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    for method, rs in by_method.items():
        ms = sum(float(r["frame_modeled_gpu_ms"]) for r in rs) / len(rs)
        rays = sum(float(r["rays"]) for r in rs) / len(rs)
        total = ms * a.frames * 1e-3
        left = (a.goal_s - total) / a.frames * 1e3
        print(f"| {method} | {len(rs)} | {rays * 1e-6:.2f} | {ms:.2f} | {rays / ms * 1e-6:.2f} | {total:.1f} | "
              f"{left:.1f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
