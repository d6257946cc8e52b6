#!/usr/bin/python3
"""One measured-vs-modeled table from `raycoh table` CSVs (scripts/gpu-check).

Usage: gpu_check_summary.py TABLE.csv [TABLE.csv ...]   (markdown on stdout)

scaling-WxH.csv files (gpu-check --scaling) give one more table: the trace kernel per size, measured beside modeled.

Per scene and method (primary pass and secondary methods), over all frames (total rays / total time):
  speed table     cuda (measured MRay/s, ratio to noopt), cuda:bvh=cwbvh (measured), simt (MODELED MRay/s,
                  its limiter), and modeled / measured for the BVH2 kernel;
  pipeline table  end to end on the device (pipeline=device rows): measured GPU stage times (generation, keys,
                  sort, permute, trace) and the measured span gpu_e2e_ms with its ratio to noopt, beside simt's
                  MODELED stages and modeled_e2e_ms;
  counters table  cuda:counters=on against simt: SIMT efficiency and lines per ray (both count the same
                  traversal; they should be equal).
Measured and modeled figures stay in separate columns; nothing modeled is added to anything measured.
Only the standard library, so that it runs on a GPU machine's Python as well as Debian's.
"""
import csv
import sys
from collections import OrderedDict

from result_key import row_layout, tracer_parameters


def tracer_label(row):
    params = tracer_parameters(row)
    name = row["tracer"]
    if name == "cuda":
        if params.get("counters") == "on":
            return "cuda:counters"
        if row_layout(row) == "cwbvh":
            return "cuda:cwbvh-shared" if params.get("stack") == "shared" else "cuda:cwbvh"
    if name == "simt" and row_layout(row) == "cwbvh":
        return "simt:cwbvh"
    if name in ("cuda", "simt") and params.get("traversal") == "classic":  # the BVH2 kernel before 2026-11
        return name + ":classic"
    return name


def number(text):
    try:
        return float(text)
    except (TypeError, ValueError):
        return None


STAGES = ("gen_ms", "key_ms", "sort_ms", "permute_ms", "trace_ms")
MODELED_STAGES = ("modeled_gen_ms", "modeled_key_ms", "modeled_sort_ms", "modeled_permute_ms", "modeled_ms",
                  "modeled_e2e_ms")


def collect(paths):
    """cells[(scene, method)][tracer] = {rays, ms, modeled_ms, eff, lines, limiter}"""
    cells = OrderedDict()
    seen = set()  # noopt and the primary pass are in every file: count each (scene, method, tracer, frame) once
    for path in paths:
        with open(path, newline="") as f:
            for row in csv.DictReader(f):
                if row.get("run_under"):  # under a profiler or sanitizer: not a timing
                    continue
                method = "primary" if row["pass"] == "primary" else row["method"]
                tracer = tracer_label(row)
                if (row["scene"], method, tracer, row["frame"]) in seen:
                    continue
                seen.add((row["scene"], method, tracer, row["frame"]))
                cell = cells.setdefault((row["scene"], method), {})
                acc = cell.setdefault(tracer, {"rays": 0.0, "ms": 0.0, "modeled_ms": 0.0, "eff": [], "lines": [],
                                               "limiter": set()})
                rays, ms, modeled = number(row["rays"]), number(row["trace_ms"]), number(row["modeled_ms"])
                acc["rays"] += rays or 0.0
                acc["ms"] += ms or 0.0
                acc["modeled_ms"] += modeled or 0.0
                for field in STAGES + MODELED_STAGES + ("gpu_e2e_ms",):
                    if field not in ("trace_ms", "modeled_ms"):  # summed above as ms and modeled_ms
                        acc[field] = acc.get(field, 0.0) + (number(row.get(field)) or 0.0)
                acc["device"] = acc.get("device", False) or row.get("pipeline") == "device"
                for name, field in (("eff", "simt_efficiency"), ("lines", "lines_per_ray")):
                    if number(row.get(field)) is not None:
                        acc[name].append(number(row[field]))
                if tracer == "simt":
                    acc.setdefault("presets", set()).add(tracer_parameters(row).get("preset", "?"))
                if row.get("modeled_limiter"):
                    acc["limiter"].add(row["modeled_limiter"])
    return cells


def mray(acc, modeled=False):
    ms = acc["modeled_ms"] if modeled else acc["ms"]
    return acc["rays"] / ms / 1000.0 if acc and ms > 0 else None


def fmt(value, digits=1):
    return "–" if value is None else f"{value:.{digits}f}"


def ratio(value, base):
    return None if value is None or not base else value / base


def speed_table(cells):
    out = ["| scene | method | cuda MRay/s (measured) | ×noopt | cuda:cwbvh MRay/s (measured) | ×noopt | "
           "simt MRay/s (MODELED) | ×noopt | limiter | modeled / measured MRay/s |",
           "|---|---|---:|---:|---:|---:|---:|---:|---|---:|"]
    for (scene, method), cell in cells.items():
        base = cells.get((scene, "noopt"), {})
        cuda, cw, simt = cell.get("cuda"), cell.get("cuda:cwbvh"), cell.get("simt")
        b_cuda = mray(base.get("cuda")) if base.get("cuda") else None
        b_cw = mray(base.get("cuda:cwbvh")) if base.get("cuda:cwbvh") else None
        b_simt = mray(base.get("simt"), True) if base.get("simt") else None
        m_cuda = mray(cuda) if cuda else None
        m_cw = mray(cw) if cw else None
        m_simt = mray(simt, True) if simt else None
        out.append(f"| {scene} | {method} | {fmt(m_cuda)} | {fmt(ratio(m_cuda, b_cuda), 3)} | {fmt(m_cw)} | "
                   f"{fmt(ratio(m_cw, b_cw), 3)} | {fmt(m_simt)} | {fmt(ratio(m_simt, b_simt), 3)} | "
                   f"{'/'.join(sorted(simt['limiter'])) if simt else '–'} | {fmt(ratio(m_simt, m_cuda), 2)} |")
    return out


def per_ray_rate(acc, field):
    """MRay/s of a summed time column, None where it is empty."""
    return acc["rays"] / acc[field] / 1000.0 if acc and acc.get(field) else None


def pipeline_table(cells):
    out = ["| scene | method | gen | key | sort | permute | trace | span gpu_e2e_ms (measured) | MRay/s | ×noopt | "
           "gen | key | sort | permute | trace | modeled_e2e_ms (MODELED) | ×noopt |",
           "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for (scene, method), cell in cells.items():
        cuda, simt = cell.get("cuda"), cell.get("simt")
        if not cuda or not cuda.get("device"):
            continue
        base = cells.get((scene, "noopt"), {})
        b_cuda, b_simt = base.get("cuda"), base.get("simt")
        measured = " | ".join(fmt(cuda["ms" if f == "trace_ms" else f], 3) for f in STAGES)
        rate = per_ray_rate(cuda, "gpu_e2e_ms")
        modeled = " | ".join(fmt(simt[f], 3) if simt else "–" for f in MODELED_STAGES)
        m_rate = per_ray_rate(simt, "modeled_e2e_ms") if simt else None
        out.append(f"| {scene} | {method} | {measured} | {fmt(cuda['gpu_e2e_ms'] or None, 3)} | {fmt(rate)} | "
                   f"{fmt(ratio(rate, per_ray_rate(b_cuda, 'gpu_e2e_ms')), 3)} | {modeled} | "
                   f"{fmt(ratio(m_rate, per_ray_rate(b_simt, 'modeled_e2e_ms') if b_simt else None), 3)} |")
    return out


def counters_table(cells):
    out = ["| scene | method | SIMT eff. cuda:counters | SIMT eff. simt | lines/ray cuda:counters | lines/ray simt "
           "| equal |", "|---|---|---:|---:|---:|---:|---|"]
    for (scene, method), cell in cells.items():
        c, s = cell.get("cuda:counters"), cell.get("simt")
        if not c or not s:
            continue
        ce, se = sum(c["eff"]) / max(len(c["eff"]), 1), sum(s["eff"]) / max(len(s["eff"]), 1)
        cl, sl = sum(c["lines"]) / max(len(c["lines"]), 1), sum(s["lines"]) / max(len(s["lines"]), 1)
        equal = "yes" if c["eff"] == s["eff"] and c["lines"] == s["lines"] else "**no**"
        out.append(f"| {scene} | {method} | {ce:.4f} | {se:.4f} | {cl:.3f} | {sl:.3f} | {equal} |")
    return out


def scaling_table(paths):
    """scaling-WxH.csv files (gpu-check --scaling): per scene, size and method the cuda trace kernel's measured ms
    beside simt's modeled ms, their quotient and both ratios to noopt (per ray)."""
    cells = OrderedDict()
    for path in paths:
        with open(path, newline="") as f:
            for row in csv.DictReader(f):
                if row.get("run_under"):  # under a profiler or sanitizer: not a timing
                    continue
                method = "primary" if row["pass"] == "primary" else row["method"]
                cell = cells.setdefault((row["scene"], f"{row['width']}x{row['height']}", method), {})
                if row["tracer"] == "cuda":
                    cell.update(rays=number(row["rays"]), ms=number(row["trace_ms"]))
                elif row["tracer"] == "simt":
                    cell.update(modeled=number(row["modeled_ms"]), limiter=row["modeled_limiter"])
    out = ["| scene | size | method | rays | trace ms (measured) | modeled ms (MODELED) | modeled ms / measured ms | "
           "×noopt measured | ×noopt modeled | limiter |", "|---|---|---|---:|---:|---:|---:|---:|---:|---|"]
    for (scene, size, method), c in sorted(cells.items(), key=lambda kv: (kv[0][0], int(kv[0][1].split("x")[0]))):
        b = cells.get((scene, size, "noopt"), {})
        if not c.get("ms") or not c.get("modeled") or not b.get("ms") or not b.get("modeled"):
            continue
        per_ray = c["rays"] / b["rays"]
        out.append(f"| {scene} | {size} | {method} | {int(c['rays'])} | {c['ms']:.4f} | {c['modeled']:.4f} | "
                   f"{c['modeled'] / c['ms']:.2f} | {b['ms'] / c['ms'] * per_ray:.3f} | "
                   f"{b['modeled'] / c['modeled'] * per_ray:.3f} | {c['limiter']} |")
    return out


def simulated_device(paths):
    """The `device` text of the first cuda row from a simulator build (GPGPU-Sim), or None for hardware."""
    for path in paths:
        with open(path, newline="") as f:
            for row in csv.DictReader(f):
                if row["tracer"] == "cuda" and row.get("device", "").startswith("simulated"):
                    return row["device"]
    return None


def summary(cells, scaling):
    out = []
    if scaling:
        out += ["## Trace kernel from a latency-bound batch to many waves: measured (cuda) beside MODELED (simt)\n",
                "\n".join(scaling_table(scaling)) + "\n"]
    if cells:
        presets = sorted({p for cell in cells.values() for p in cell.get("simt", {}).get("presets", ())})
        out += ["## Trace kernel: measured (cuda) beside modeled (simt, preset " + ", ".join(presets or ["–"]) + ")\n",
                "\n".join(speed_table(cells)),
                "\n## End to end on the device: measured GPU stages (ms, summed over frames) beside the MODELED "
                "stages\n", "\n".join(pipeline_table(cells)),
                "\n## Warp counters: cuda:counters=on against simt (the same traversal counted twice)\n",
                "\n".join(counters_table(cells))]
    return "\n".join(out)


def main(argv):
    if len(argv) < 2:
        print(__doc__, file=sys.stderr)
        return 2
    import os
    paths = [p for p in argv[1:] if os.path.exists(p)]
    scaling = [p for p in paths if os.path.basename(p).startswith("scaling-")]
    cells = collect([p for p in paths if p not in scaling])
    if not cells and not scaling:
        print("gpu_check_summary: no rows in " + ", ".join(argv[1:]), file=sys.stderr)
        return 1
    text = summary(cells, scaling)
    device = simulated_device(paths)
    if device:  # a simulator build (scripts/gpu-check dry-run): its cuda figures are a second model's, not hardware
        text = (f"**SIMULATED, not hardware**: the cuda figures come from {device}; in functional mode their times "
                "are the simulator's wall time and mean nothing (the counters do).\n\n" +
                text.replace("(measured)", "(SIMULATED)").replace("measured", "SIMULATED"))
    print(text)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
