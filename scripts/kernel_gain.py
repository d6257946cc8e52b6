#!/usr/bin/python3
"""The coherence gain against the quality of the trace kernel, and the model's prediction beside the measurement.

Usage: kernel_gain.py PREDICTION.csv [...] [--measured MEASURED.csv ...]   (markdown on stdout)

PREDICTION.csv: `raycoh table` rows of the simt tracer (MODELED) for the three kernels of the `cuda` tracer, made
and committed before any hardware run (results/kernels/README.md): simt:traversal=classic (the BVH2 kernel before
2026-11), simt (the tuned BVH2 kernel) and simt:bvh=cwbvh. MEASURED.csv: rows of the same methods and scenes on
cuda:traversal=classic, cuda, cuda:bvh=cwbvh and cuda:bvh=cwbvh,stack=shared (scripts/gpu-check --kernels). Tables:
  prediction  per scene, method and kernel: predicted MRay/s and ratio to noopt (MODELED) beside the measured ones
              and the miss of the ratio in percent;
  gain        per scene and method, per kernel: the trace-only and the end-to-end ratio to noopt, measured (cuda;
              end to end: the device pipeline's span gpu_e2e_ms) and MODELED (simt; modeled_e2e_ms), side by side.
Measured and modeled figures stay in separate columns and are never combined into one figure. Standard library only.
"""
import importlib.util
import pathlib
import sys

_spec = importlib.util.spec_from_file_location("gpu_check_summary",
                                               pathlib.Path(__file__).with_name("gpu_check_summary.py"))
summary = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(summary)

# (kernel, its cuda label, the simt label that models it). The model does not tell a stack in shared memory from
# one in local memory (both one L1 wavefront an access, and local lines are not in its cache model): the CWBVH
# kernel's two stacks share one prediction.
KERNELS = (("classic", "cuda:classic", "simt:classic"), ("tuned", "cuda", "simt"), ("cwbvh", "cuda:cwbvh", "simt:cwbvh"),
           ("cwbvh stack=shared", "cuda:cwbvh-shared", "simt:cwbvh"))


def rate(acc, field):
    """MRay/s from the summed rays and a summed time column (trace_ms is `ms`, modeled_ms `modeled_ms`)."""
    if not acc:
        return None
    ms = acc.get({"trace_ms": "ms"}.get(field, field))
    return acc["rays"] / ms / 1000.0 if ms else None


def gain(cells, scene, method, tracer, field):
    base = cells.get((scene, "noopt"), {}).get(tracer)
    return summary.ratio(rate(cells.get((scene, method), {}).get(tracer), field), rate(base, field))


def prediction_table(predicted, measured):
    out = ["| scene | method | kernel | predicted MRay/s (MODELED) | measured MRay/s | ×noopt predicted | "
           "×noopt measured | ratio miss |", "|---|---|---|---:|---:|---:|---:|---:|"]
    for (scene, method), cell in predicted.items():
        for kernel, cuda, simt in KERNELS:
            if simt not in cell:
                continue
            p, m = rate(cell[simt], "modeled_ms"), rate(measured.get((scene, method), {}).get(cuda), "trace_ms")
            pg, mg = gain(predicted, scene, method, simt, "modeled_ms"), gain(measured, scene, method, cuda, "trace_ms")
            miss = f"{(pg / mg - 1) * 100:+.1f}%" if pg and mg else "–"
            out.append(f"| {scene} | {method} | {kernel} | {summary.fmt(p)} | {summary.fmt(m)} | "
                       f"{summary.fmt(pg, 3)} | {summary.fmt(mg, 3)} | {miss} |")
    return out


def gain_table(predicted, measured):
    head = "| scene | method |"
    rule = "|---|---|"
    for kernel, _, _ in KERNELS:
        head += f" {kernel} trace (measured) | {kernel} e2e (measured) | {kernel} trace (MODELED) | " \
                f"{kernel} e2e (MODELED) |"
        rule += "---:|---:|---:|---:|"
    out = [head, rule]
    for (scene, method) in predicted:
        if method in ("noopt", "primary"):
            continue
        row = f"| {scene} | {method} |"
        for _, cuda, simt in KERNELS:
            row += " | ".join([""] + [summary.fmt(v, 3) for v in (
                gain(measured, scene, method, cuda, "trace_ms"), gain(measured, scene, method, cuda, "gpu_e2e_ms"),
                gain(predicted, scene, method, simt, "modeled_ms"),
                gain(predicted, scene, method, simt, "modeled_e2e_ms"))]) + " |"
        out.append(row.replace("| |", "|"))
    return out


def main(argv):
    args = argv[1:]
    cut = args.index("--measured") if "--measured" in args else len(args)
    if cut == 0:
        print(__doc__, file=sys.stderr)
        return 2
    predicted = summary.collect(args[:cut])
    measured = summary.collect([p for p in args[cut + 1:] if pathlib.Path(p).exists()])
    if not predicted:
        print(f"kernel_gain: no rows in {', '.join(args[:cut])}", file=sys.stderr)
        return 1
    text = ("## The model's prediction (MODELED, committed before the hardware run) beside the measurement\n\n" +
            "\n".join(prediction_table(predicted, measured)) +
            "\n\n## Coherence gain (ratio to noopt) against the trace kernel: measured (cuda) and MODELED (simt)\n\n" +
            "\n".join(gain_table(predicted, measured)))
    device = summary.simulated_device([p for p in args[cut + 1:] if pathlib.Path(p).exists()])
    if device:  # rows of a simulator build: a second model's figures, and in functional mode no time at all
        text = (f"**SIMULATED, not hardware**: the measured columns come from {device}; in functional mode their "
                "times are the simulator's wall time and mean nothing.\n\n" +
                text.replace("measured", "SIMULATED"))
    print(text)
    if not measured:
        print("\nNo measured rows given: every measured column is –.")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
