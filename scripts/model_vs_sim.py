#!/usr/bin/python3
"""Summary of scripts/model-vs-sim: one row per cell (scene x size x method) from OUT/runs/*.csv.

Simulator cycles: the `cuda` row's trace_ms (CUDA events in simulated time, GPGPU_SIM_EVENT_CYCLES=1) x the
simulated core clock; the simulator's own per-kernel gpu_sim_cycle is in OUT/runs/*.kernels.txt (equal within the
event recording's few cycles). Model cycles: the `simt` row's modeled_ms x the same clock. Error: model / sim - 1.
Ratios to noopt: noopt's cycles / the cell's, on each side. Writes OUT/cells.csv, OUT/table.md and the figure.
Usage: scripts/model_vs_sim.py OUT FIGURE.png
"""
import csv
import glob
import os
import re
import sys

CLOCK_MHZ = 1132.0  # simt/gpu_presets.cpp gpgpusim_rtx3070 (the simulator's cfg:31)
SCENES = ["cornell", "voxels", "sibenik", "country_kitchen"]
METHODS = ["primary", "noopt", "ours", "ours:order=group", "contiguous", "noopt+twopoint", "noopt+mlhcc"]


def label(row):
    name = row["method"]
    if "order=group" in row["generator_params"] and "group" not in name:
        name += " (group order)"
    return name


def resident_per_sm(kernels_file):
    m = re.search(r"CTA/core = (\d+)", open(kernels_file).read()) if os.path.exists(kernels_file) else None
    return int(m.group(1)) * 4 if m else 36  # blocks of 128 threads


def read_runs(out):
    cells, repeats = {}, []
    for path in sorted(glob.glob(os.path.join(out, "runs", "*.csv"))):
        if path.endswith(".model.csv"):
            continue
        m = re.search(r"_(\d+x\d+)_sms(\d+)_(gen|enc)\.csv$", path)
        size, sms, part = m.group(1), int(m.group(2)), m.group(3)
        resident = resident_per_sm(path[:-4] + ".kernels.txt")
        rows = list(csv.DictReader(open(path)))
        for r in rows:
            if r["tracer"] not in ("cuda", "simt"):
                continue
            key = (r["scene"], size, label(r))
            if part == "enc" and key[2] in ("primary", "noopt"):
                if r["tracer"] == "cuda":
                    repeats.append((key, float(r["trace_ms"]) * CLOCK_MHZ * 1e3))
                if key in cells:
                    continue
            c = cells.setdefault(key, {"sms": sms, "resident": resident, "revision": r["git_revision"]})
            c["rays"] = int(r["rays"])
            if r["tracer"] == "cuda":
                c["sim_cycles"] = float(r["trace_ms"]) * CLOCK_MHZ * 1e3
            else:
                c["model_cycles"] = float(r["modeled_ms"]) * CLOCK_MHZ * 1e3
                c["limiter"] = r["modeled_limiter"]
                c["simt_eff"] = float(r["simt_efficiency"])
                c["l1_miss"] = float(r["l1_misses_per_ray"])
        read_model_rerun(path[:-4] + ".model.csv", size, cells)
    return cells, repeats


def read_model_rerun(path, size, cells):
    """The current model on the same batch (model-vs-sim --model-only), beside the model that ran with the sim."""
    if not os.path.exists(path):
        return
    for r in csv.DictReader(open(path)):
        key = (r["scene"], size, label(r))
        if r["tracer"] == "simt" and key in cells and "model_now" not in cells[key]:
            cells[key]["model_now"] = float(r["modeled_ms"]) * CLOCK_MHZ * 1e3
            cells[key]["limiter_now"] = r["modeled_limiter"]
            cells[key]["revision_now"] = r["git_revision"]


def with_ratios(cells):
    rows = []
    for (scene, size, method), c in cells.items():
        if "sim_cycles" not in c or "model_cycles" not in c:
            continue
        base = cells.get((scene, size, "noopt"), {})
        waves = c["rays"] / (32.0 * c["resident"] * c["sms"])
        row = {"scene": scene, "size": size, "method": method, "rays": c["rays"], "waves": waves,
               "sim_cycles": c["sim_cycles"], "model_cycles": c["model_cycles"],
               "error": c["model_cycles"] / c["sim_cycles"] - 1, "limiter": c["limiter"],
               "simt_efficiency": c["simt_eff"], "l1_misses_per_ray": c["l1_miss"], "sms": c["sms"],
               "git_revision": c["revision"]}
        if "sim_cycles" in base and "model_cycles" in base:
            row["sim_ratio"] = base["sim_cycles"] / c["sim_cycles"]
            row["model_ratio"] = base["model_cycles"] / c["model_cycles"]
            row["ratio_error"] = row["model_ratio"] / row["sim_ratio"] - 1
        if "model_now" in c:
            row.update(model_now=c["model_now"], error_now=c["model_now"] / c["sim_cycles"] - 1,
                       limiter_now=c["limiter_now"], revision_now=c["revision_now"])
            if "model_now" in base and "sim_cycles" in base:
                row["model_ratio_now"] = base["model_now"] / c["model_now"]
                row["ratio_error_now"] = row["model_ratio_now"] / row["sim_ratio"] - 1
        rows.append(row)

    def order(r):
        w, h = (int(x) for x in r["size"].split("x"))
        scene = SCENES.index(r["scene"]) if r["scene"] in SCENES else 99
        method = METHODS.index(r["method"]) if r["method"] in METHODS else 99
        return (w * h, scene, method)
    return sorted(rows, key=order)


def write_outputs(out, rows, repeats):
    cols = ["scene", "size", "sms", "method", "rays", "waves", "sim_cycles", "model_cycles", "error", "limiter",
            "sim_ratio", "model_ratio", "ratio_error", "simt_efficiency", "l1_misses_per_ray", "git_revision",
            "model_now", "error_now", "limiter_now", "model_ratio_now", "ratio_error_now", "revision_now"]
    with open(os.path.join(out, "cells.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=cols, extrasaction="ignore")
        w.writeheader()
        w.writerows(rows)
    pct = lambda x: "" if x is None else f"{x * 100:+.0f}%"
    num = lambda x, f="{:.2f}": "" if x is None else f.format(x)
    now = any("model_now" in r for r in rows)
    extra = " MODELED now | error now | ratio now | ratio error now |" if now else ""
    lines = ["| scene | size | method | rays | waves | SIMULATED cycles | MODELED cycles | error | limiter | "
             "ratio to noopt SIMULATED | MODELED | ratio error |" + extra,
             "|" + "---|" * 3 + "---:|" * 5 + "---|" + "---:|" * 3 + "---:|" * (4 if now else 0)]
    for r in rows:
        line = (f"| {r['scene']} | {r['size']} | {r['method']} | {r['rays']} | {r['waves']:.2f} | "
                f"{r['sim_cycles']:,.0f} | {r['model_cycles']:,.0f} | {pct(r['error'])} | {r['limiter']} | "
                f"{num(r.get('sim_ratio'))} | {num(r.get('model_ratio'))} | {pct(r.get('ratio_error'))} |")
        if now:
            line += (f" {num(r.get('model_now'), '{:,.0f}')} | {pct(r.get('error_now'))} | "
                     f"{num(r.get('model_ratio_now'))} | {pct(r.get('ratio_error_now'))} |")
        lines.append(line)
    cells = {(r["scene"], r["size"], r["method"]): r for r in rows}
    notes = [f"- {k[0]} {k[1]} {k[2]} traced again in the enc part: {cyc:,.0f} SIMULATED cycles against "
             f"{cells[k]['sim_cycles']:,.0f} ({cyc / cells[k]['sim_cycles'] - 1:+.1%})"
             for k, cyc in repeats if k in cells]
    with open(os.path.join(out, "table.md"), "w") as f:
        revs = sorted({r["git_revision"] for r in rows})
        revs_now = sorted({r["revision_now"] for r in rows if "revision_now" in r})
        f.write("SIMULATED: GPGPU-Sim performance mode (not hardware); MODELED: simt:preset=gpgpusim-rtx3070 in the "
                f"simulator's process (revision {', '.join(revs)})"
                + (f"; MODELED now: the current model on the same batch (revision {', '.join(revs_now)})"
                   if revs_now else "")
                + ". Cycles at 1132 MHz; error = MODELED / SIMULATED - 1.\n\n" + "\n".join(lines) + "\n")
        if notes:
            f.write("\nRepeatability (the same batch traced again after another kernel):\n\n" + "\n".join(notes) + "\n")


def plot(rows, path):
    if not rows:
        return
    os.environ.setdefault("MPLBACKEND", "Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(9.6, 5.6))
    markers = dict(zip(SCENES, "osD^"))
    sizes = sorted({r["size"] for r in rows}, key=lambda s: eval(s.replace("x", "*")))
    colors = dict(zip(sizes, ["tab:blue", "tab:orange", "tab:green", "tab:red", "tab:purple", "tab:brown"]))
    for scene in SCENES:
        for size in sizes:
            pts = [r for r in rows if r["scene"] == scene and r["size"] == size]
            if not pts:
                continue
            waves = max(p["waves"] for p in pts if p["method"] != "primary" or len(pts) == 1)
            # Filled: the current model (model-vs-sim --model-only) where it ran; hollow: the model in the sim's run.
            ax.scatter([p["sim_cycles"] for p in pts], [p["model_cycles"] for p in pts],
                       marker=markers.get(scene, "x"), facecolors="none", edgecolors=colors[size], alpha=0.6)
            now = [p for p in pts if "model_now" in p]
            if now:
                ax.scatter([p["sim_cycles"] for p in now], [p["model_now"] for p in now],
                           marker=markers.get(scene, "x"), color=colors[size], alpha=0.85,
                           label=f"{scene} {size}, {pts[0]['sms']} SMs ({waves:.1f} waves of secondary rays)")
    lo = min(min(r["sim_cycles"], r["model_cycles"]) for r in rows) / 1.5
    hi = max(max(r["sim_cycles"], r["model_cycles"]) for r in rows) * 1.5
    ax.plot([lo, hi], [lo, hi], "k-", lw=0.8, label="model = simulator")
    ax.fill_between([lo, hi], [lo * 0.8, hi * 0.8], [lo * 1.2, hi * 1.2], color="k", alpha=0.08, label="±20%")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlim(lo, hi)
    ax.set_ylim(lo, hi)
    ax.set_xlabel("SIMULATED trace-kernel cycles (GPGPU-Sim RTX 3070 config, not hardware)")
    ax.set_ylabel("MODELED trace-kernel cycles (simt:preset=gpgpusim-rtx3070)")
    ax.set_title("MODELED vs SIMULATED trace kernel, one point per cell\n(filled: the current model; "
                 "hollow: before the bank, PTX and in-order rules)", fontsize=9)
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0)
    fig.tight_layout()
    os.makedirs(os.path.dirname(path), exist_ok=True)
    fig.savefig(path, dpi=120)


def main():
    if len(sys.argv) != 3:
        print("usage: scripts/model_vs_sim.py OUT FIGURE.png", file=sys.stderr)
        sys.exit(2)
    out, figure = sys.argv[1], sys.argv[2]
    if not glob.glob(os.path.join(out, "runs", "*_gen.csv")) + glob.glob(os.path.join(out, "runs", "*_enc.csv")):
        print(f"model_vs_sim.py: no runs/*_gen.csv or *_enc.csv under {out} (scripts/model-vs-sim writes them)",
              file=sys.stderr)
        sys.exit(2)
    cells, repeats = read_runs(out)
    rows = with_ratios(cells)
    write_outputs(out, rows, repeats)
    plot(rows, figure)
    print(f"model_vs_sim: {len(rows)} cells -> {out}/cells.csv, table.md, {figure}")


if __name__ == "__main__":
    main()
