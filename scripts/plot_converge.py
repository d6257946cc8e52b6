#!/usr/bin/python3
"""Error against time curves from `raycoh converge` CSVs (one or more, e.g. one per scene): one line per generator,
one row of panels per scene, one panel per clock.

Clocks (--clock, comma-separated): wall_s, the cumulative wall-clock time of the frames; trace_s, the cumulative
time of the CPU tracer calls; modeled_gpu_s, the cumulative MODELED time of the same frames on the `simt` tracer's
GPU (`converge --gpu-model`; never added to a measured time); gpu_s, the cumulative GPU time of the frames rendered
by the device path tracer (`converge --device cuda`: CUDA events, MEASURED on a GPU or SIMULATED under GPGPU-Sim,
as the rows' gpu_clock says; a panel never mixes the two). The default is wall_s and, where the CSV has them,
modeled_gpu_s and gpu_s beside it. y is the error of the running mean against the reference
(--metric rel_mse by default; mse, rmse on log axes; psnr, ssim on a linear axis). With <csv stem>-summary.csv
beside it, the equal-time error ratio and equal-error speedup of each clock are written into its legend.

usage: plot_converge.py converge.csv [more.csv ...] --out curves.png [--metric rel_mse|mse|rmse|psnr|ssim]
                        [--clock wall_s|trace_s|modeled_gpu_s|gpu_s[,...]]
"""
import argparse
import csv
import os
from collections import defaultdict

from plotlib import TRACER_COLUMNS, fail, footer, number, plt, read_csv, save
from result_key import result_label

CLOCKS = {
    "wall_s": "wall-clock time of the frames (s), measured",
    "trace_s": "CPU trace time (s), measured",
    "modeled_gpu_s": "GPU time (s), MODELED",
    "gpu_s": "device path tracer's GPU time (s), {kind} (CUDA events)",
}


def device_clock(rows, scene):
    """'MEASURED' or 'SIMULATED' from the scene's rows' gpu_clock; fails where a scene mixes the two."""
    kinds = {r.get("gpu_clock", "") for r in rows if r["scene"] == scene and number(r, "gpu_s") > 0}
    if len(kinds) != 1 or not kinds <= {"measured", "simulated"}:
        fail(f"{scene}: gpu_s rows of gpu_clock {sorted(kinds) or 'none'}; one of measured or simulated per plot")
    return kinds.pop().upper()


def summary_clock(clock, rows):
    """The summary CSV's clock name of a curve clock: wall, trace, modeled_gpu, measured_gpu or simulated_gpu."""
    if clock != "gpu_s":
        return clock[:-2]
    kinds = {r.get("gpu_clock") for r in rows} - {None, ""}
    return f"{kinds.pop()}_gpu" if len(kinds) == 1 else ""


def short_model(row):
    """'simt[preset=rtx3060]' from the typed gpu_preset column (gpu_model keeps every parameter); '' without one."""
    return result_label("simt", preset=row["gpu_preset"]) if row.get("gpu_preset") else row.get("gpu_model", "")


def summary_notes(path, clock):
    """(scene, method) -> legend note from the summary CSV of the same run (if present); clock as the summary
    names it."""
    notes = {}
    summary = os.path.splitext(path)[0] + "-summary.csv"
    if not os.path.isfile(summary):
        return notes
    with open(summary, newline="") as f:
        for r in csv.DictReader(f):
            if r.get("clock") == clock:
                try:
                    notes[(r.get("scene"), r["method"], r.get("render_device", ""))] = (
                        f"error x{float(r['equal_time_error_ratio']):.2f} at equal time, "
                        f"{float(r['equal_error_speedup']):.2f}x at equal error")
                except (KeyError, ValueError):
                    pass
    return notes


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("csv", nargs="+", help="CSVs written by raycoh converge")
    ap.add_argument("--out", required=True, help="figure file (.png, .pdf, .svg)")
    ap.add_argument("--metric", choices=["rel_mse", "mse", "rmse", "psnr", "ssim"], default="rel_mse")
    ap.add_argument("--clock", default=None,
                    help="comma-separated clocks: wall_s, trace_s, modeled_gpu_s, gpu_s (default wall_s and, "
                         "when present, modeled_gpu_s and gpu_s)")
    a = ap.parse_args()

    rows = read_csv(a.csv, ["scene", "method", "frame", a.metric, "gpu_preset"] + TRACER_COLUMNS)
    if a.clock is None:
        clocks = ["wall_s"] + [c for c in ("modeled_gpu_s", "gpu_s")
                               if any(r.get(c) not in (None, "", "nan") for r in rows)]
    else:
        clocks = [c.strip() for c in a.clock.split(",") if c.strip()]
        for c in clocks:
            if c not in CLOCKS:
                fail(f"--clock {c}: expected one of {', '.join(CLOCKS)}")
        if not clocks:
            fail("--clock: empty list")
    read_csv(a.csv, clocks)  # every clock asked for must be a column
    scenes = []
    for r in rows:
        if r["scene"] not in scenes:
            scenes.append(r["scene"])
    log = a.metric in ("rel_mse", "mse", "rmse")
    # Curves of one method rendered on several devices or forms (converge --device cuda and cuda:pipeline=fused
    # CSVs together) stay apart, each named by its render_device.
    devices = {r.get("render_device", "") for r in rows}
    style = {d: ls for d, ls in zip(sorted(devices), ["-", "--", ":", "-."] * len(devices))}
    methods = list(dict.fromkeys(r["method"] for r in rows))  # one colour per method, whatever its device
    fig, axes = plt.subplots(len(scenes), len(clocks), figsize=(6 * len(clocks), 4.2 * len(scenes)), squeeze=False)
    for ci, clock in enumerate(clocks):
        curves = defaultdict(list)
        for r in rows:
            t, e = number(r, clock), number(r, a.metric)
            if t > 0 and e == e:
                curves[(r["scene"], r["method"], r.get("render_device", ""))].append((t, e))
        if not curves:
            fail(f"no rows with a positive {clock} and a {a.metric} value")
        notes = {}
        for path in a.csv:
            notes.update(summary_notes(path, summary_clock(clock, [r for r in rows if number(r, clock) > 0])))
        for si, scene in enumerate(scenes):
            ax = axes[si][ci]
            for (s, method, device), pts in curves.items():
                if s != scene:
                    continue
                pts.sort()
                key = (s, method, device)
                label = method + (f" [{device}]" if len(devices) > 1 else "")
                label += f" ({notes[key]})" if key in notes else ""
                ax.plot([p[0] for p in pts], [p[1] for p in pts], label=label, linewidth=1.2,
                        linestyle=style[device], color=f"C{methods.index(method) % 10}")
            ax.set_xscale("log")
            if log:
                ax.set_yscale("log")
            kind = device_clock(rows, scene) if clock == "gpu_s" else ""
            ax.set_xlabel(CLOCKS[clock].format(kind=kind))
            ax.set_ylabel(a.metric)
            title = scene + (" — MODELED GPU clock" if clock == "modeled_gpu_s" else "")
            title += f" — {kind} GPU clock" if kind else ""
            if clock == "modeled_gpu_s":
                models = sorted({short_model(r) for r in rows if r["scene"] == scene} - {""})
                if models:
                    title += f"\n{', '.join(models)}"
            ax.set_title(title, fontsize=10)
            ax.grid(True, which="both", alpha=0.3)
            if ax.lines:
                ax.legend(fontsize=8)
    fig.tight_layout()
    footer(fig, rows)
    save(fig, a.out)


if __name__ == "__main__":
    main()
