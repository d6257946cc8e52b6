#!/usr/bin/env python3
"""Each bounce's trace speed on the device path tracer, from `raycoh converge --device cuda` rows: does the first
bounce's coherence carry into the second?

Per scene, device form (render_device: cuda, or cuda:pipeline=fused) and method: the first and second bounces'
trace speed over the run's frames (each frame's wave rays ÷ its wave's trace ms: gpu_first_trace_ms /
first_wave_rays, gpu_second_trace_ms / second_wave_rays), as the median with its order-statistic 95% interval; and
each bounce's speed ratio to noopt's (same scene and form), with the bootstrap 95% interval of
scripts/speed_interval.py (each frame's time per ray as one repeat). A ratio is called faster or slower only where
its interval excludes 1, otherwise indistinguishable. The clock (gpu_clock: measured on a GPU, simulated under
GPGPU-Sim) heads each table; figures of the two clocks are never mixed. With the first bounce fused, its kernel
(generation included) is the first wave's trace.

Usage: bounce_speed.py CONVERGE.csv [CONVERGE.csv ...]   (markdown on stdout). Standard library only.
"""
import csv
import sys
from collections import defaultdict

from speed_interval import median_interval, speed_ratio

NEEDED = ("scene", "method", "frame", "render_device", "gpu_clock", "gpu_first_trace_ms", "gpu_second_trace_ms",
          "first_wave_rays", "second_wave_rays")
BOUNCES = (("first", "gpu_first_trace_ms", "first_wave_rays"), ("second", "gpu_second_trace_ms", "second_wave_rays"))


def fail(message):
    print(f"bounce_speed.py: {message}", file=sys.stderr)
    sys.exit(2)


def read(paths):
    """{(clock, scene, device): {method: {bounce: [(ms, rays) per frame]}}} of the rows rendered on the device."""
    runs = defaultdict(lambda: defaultdict(lambda: defaultdict(list)))
    for path in paths:
        try:
            with open(path, newline="") as f:
                reader = csv.DictReader(f)
                missing = [c for c in NEEDED if c not in (reader.fieldnames or [])]
                if missing:
                    fail(f"{path}: no column {missing[0]} (converge rows of the device path tracer, --device cuda)")
                for r in reader:
                    if r["render_device"] == "cpu" or r["gpu_first_trace_ms"] in ("", "nan"):
                        continue
                    key = (r["gpu_clock"], r["scene"], r["render_device"])
                    for name, ms_col, rays_col in BOUNCES:
                        ms, rays = float(r[ms_col]), float(r[rays_col])
                        if ms > 0 and rays > 0:
                            runs[key][r["method"]][name].append((ms, rays))
        except OSError as e:
            fail(f"{path}: {e.strerror}")
    if not runs:
        fail("no device rows with the bounce columns (render with converge --device cuda)")
    return runs


def speed_cell(frames):
    """Median MRay/s over frames with its interval."""
    m, lo, hi, _ = median_interval([rays / ms * 1e-3 for ms, rays in frames])
    return f"{m:.4g} [{lo:.4g}, {hi:.4g}]"


def ratio_cell(base, frames):
    """The speed ratio to base (time per ray as repeats) with its interval and verdict."""
    if not base or not frames:
        return "—"
    series = {0: ([ms / rays for ms, rays in base], 1.0)}
    ratio, lo, hi, has = speed_ratio(series, {0: ([ms / rays for ms, rays in frames], 1.0)})
    if not has:
        return f"{ratio:.3f}× (no interval: one frame)"
    word = "faster" if lo > 1 else "slower" if hi < 1 else "indistinguishable"
    return f"{ratio:.3f}× [{lo:.3f}, {hi:.3f}] {word}"


def main(argv):
    if not argv or argv[0] in ("-h", "--help"):
        print(__doc__)
        return 0 if argv else 2
    runs = read(argv)
    for (clock, scene, device), methods in sorted(runs.items()):
        print(f"### {scene}, {device}: each bounce's trace speed, {clock.upper()} (CUDA events)\n")
        print("| method | frames | first bounce MRay/s | second bounce MRay/s | first ÷ noopt | second ÷ noopt |")
        print("|---|---:|---:|---:|---:|---:|")
        base = methods.get("noopt", {})
        for method, bounces in sorted(methods.items(), key=lambda kv: (kv[0] != "noopt", kv[0])):
            first, second = bounces.get("first", []), bounces.get("second", [])
            cells = [speed_cell(first) if first else "—", speed_cell(second) if second else "—"]
            ratios = ["(base)", "(base)"] if method == "noopt" else [
                ratio_cell(base.get("first"), first), ratio_cell(base.get("second"), second)]
            print(f"| {method} | {len(first)} | {cells[0]} | {cells[1]} | {ratios[0]} | {ratios[1]} |")
        print()
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
