#!/usr/bin/python3
"""Figure of the coherence gain against the trace kernel (results/kernels/README.md).

Usage: plot_kernel_gain.py OUT.png PREDICTION.csv [...] [--measured MEASURED.csv ...]

Per scene a panel of bars: for each method (ours in tile and group order, contiguous, noopt with each encoder)
its ratio to noopt on the classic BVH2 kernel, the tuned one and the CWBVH kernel; trace only (solid) and end to
end (light). MODELED bars (simt, the committed prediction) are hatched; measured bars (cuda, where given) solid.
The two kinds are separate bars, never combined. Reads the rows as scripts/kernel_gain.py does.
"""
import importlib.util
import pathlib
import sys

import plotlib

_spec = importlib.util.spec_from_file_location("kernel_gain", pathlib.Path(__file__).with_name("kernel_gain.py"))
kg = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(kg)

COLORS = {"classic": "#9e9e9e", "tuned": "#1f77b4", "cwbvh": "#d62728", "cwbvh stack=shared": "#ff9896"}


def main(argv):
    args = argv[1:]
    if len(args) < 2:
        plotlib.fail("usage: plot_kernel_gain.py OUT.png PREDICTION.csv [...] [--measured MEASURED.csv ...]")
    out, args = args[0], args[1:]
    cut = args.index("--measured") if "--measured" in args else len(args)
    for p in args:
        if p != "--measured" and not pathlib.Path(p).is_file():
            plotlib.fail(f"{p}: no such CSV file")
    predicted = kg.summary.collect(args[:cut])
    measured = kg.summary.collect(args[cut + 1:])
    scenes = list(dict.fromkeys(scene for scene, _ in predicted))
    if not scenes:
        plotlib.fail("no rows in " + ", ".join(args[:cut]))
    plt = plotlib.plt
    fig, axes = plt.subplots(len(scenes), 1, figsize=(11, 3.2 * len(scenes)), squeeze=False)
    for ax, scene in zip(axes[:, 0], scenes):
        methods = [m for s, m in predicted if s == scene and m not in ("noopt", "primary")]
        width = 0.8 / (2 * len(kg.KERNELS))
        for k, (kernel, cuda, simt) in enumerate(kg.KERNELS):
            for j, (source, tracer, cells, trace_field, e2e_field) in enumerate((
                    ("MODELED", simt, predicted, "modeled_ms", "modeled_e2e_ms"),
                    ("measured", cuda, measured, "trace_ms", "gpu_e2e_ms"))):
                if source == "MODELED" and kernel == "cwbvh stack=shared":
                    continue  # the model does not tell the two CWBVH stacks apart: one MODELED bar (cwbvh)
                trace = [kg.gain(cells, scene, m, tracer, trace_field) for m in methods]
                e2e = [kg.gain(cells, scene, m, tracer, e2e_field) for m in methods]
                if not any(trace):
                    continue
                x = [i + (2 * k + j) * width - 0.4 + width / 2 for i in range(len(methods))]
                hatch = "//" if source == "MODELED" else None
                ax.bar(x, [v or 0 for v in trace], width, color=COLORS[kernel], hatch=hatch, edgecolor="white",
                       label=f"{kernel} trace ({source})")
                ax.scatter(x, [v or float("nan") for v in e2e], marker="_", s=120, color="black", zorder=3,
                           label="end to end" if k == 0 and j == 0 else None)
        ax.axhline(1.0, color="black", linewidth=0.8)
        ax.set_xticks(range(len(methods)))
        ax.set_xticklabels(methods, rotation=20, ha="right", fontsize=8)
        ax.set_ylabel("× noopt")
        ax.set_title(f"{scene}: ratio to noopt per trace kernel (hatched: MODELED, simt:preset=h100)", fontsize=9)
        ax.legend(fontsize=7, ncol=4)
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    print(f"wrote {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
