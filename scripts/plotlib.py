"""Shared helpers of the raycoh plot scripts: CSV reading with clear errors, matplotlib without a display.

Column meanings are documented in results/README.md. Every script exits with code 2 and one line
"<script>: error: <message>" on bad input (missing file, missing column, no rows to plot).
"""
import csv
import math
import os
import sys

os.environ.setdefault("MPLBACKEND", "Agg")
import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402,F401  (re-exported for the scripts)


def fail(message):
    sys.stderr.write(f"{os.path.basename(sys.argv[0])}: error: {message}\n")
    sys.exit(2)


def read_csv(paths, required):
    """Rows (dicts) of one or more CSV files written by raycoh; every file must have the required columns."""
    if isinstance(paths, str):
        paths = [paths]
    rows = []
    for path in paths:
        if not os.path.isfile(path):
            fail(f"{path}: no such CSV file")
        with open(path, newline="") as f:
            reader = csv.DictReader(f)
            if reader.fieldnames is None:
                fail(f"{path}: empty file (no header)")
            missing = [c for c in required if c not in reader.fieldnames]
            if missing:
                fail(f"{path}: missing column(s) {', '.join(missing)} (written by an older raycoh, or not this kind of "
                     "CSV; see results/README.md)")
            rows.extend(r for r in reader if not r.get("run_under"))  # a profiler's times are no timings
    if not rows:
        fail(f"{', '.join(paths)}: no data rows")
    return rows


def number(row, column, path_hint=""):
    text = row.get(column, "")
    try:
        return float(text)
    except ValueError:
        if text in ("", "nan"):
            return math.nan
        fail(f"{path_hint}column {column}: '{text}' is not a number")


def parse_params(text):
    """'tile=8x8,k=16,order=tile' -> {'tile': '8x8', 'k': '16', 'order': 'tile'}."""
    out = {}
    for item in filter(None, (text or "").split(",")):
        key, _, value = item.partition("=")
        out[key.strip()] = value.strip()
    return out


from result_key import TRACER_COLUMNS, row_label  # noqa: E402,F401  (re-exported for the scripts)


def tracer_label(row):
    """The tracer as a title can hold it (scripts/result_key.py): the name and, for a GPU model, its preset
    (simt[preset=rtx3060]); an embree mode (embree[mode=single]). A script that labels tracers requires
    TRACER_COLUMNS, so that a CSV written before them is refused with one line naming the file and the column."""
    return row_label(row)


# Okabe & Ito (2008): colour-blind-safe hues; noopt, the baseline, is grey.
OKABE_ITO = ["#0072B2", "#E69F00", "#009E73", "#CC79A7", "#D55E00", "#56B4E9", "#F0E442"]


def lighten(colour, shade):
    """The colour mixed with white: shade 0 is the colour, 1 white."""
    r, g, b = (int(colour[i:i + 2], 16) for i in (1, 3, 5))
    return "#" + "".join(f"{round(c + (255 - c) * shade):02x}" for c in (r, g, b))


def footer(fig, rows):
    """Resolution, frames, tracers and git revision of the rows, at the bottom of the figure."""
    res = sorted({f"{r.get('width', '?')}x{r.get('height', '?')}" for r in rows})
    frames = sorted({r["frames"] for r in rows if r.get("frames")} or
                    {str(len({r.get("frame") for r in rows if r.get("scene") == s}))
                     for s in {r.get("scene") for r in rows}})
    tracers = sorted({tracer_label(r) + (" (modeled)" if is_modeled(r) else "") for r in rows if r.get("tracer")})
    revs = sorted({r.get("git_revision", "?") for r in rows})
    fig.text(0.01, -0.01, f"{', '.join(res)}, {'/'.join(frames)} frame(s); tracer {', '.join(tracers)}; "
             f"revision {', '.join(revs)}", fontsize=7, color="#555555", ha="left", va="top")


def save(fig, out):
    directory = os.path.dirname(out)
    if directory:
        os.makedirs(directory, exist_ok=True)
    try:
        fig.savefig(out, dpi=150, bbox_inches="tight")
    except (OSError, ValueError) as e:
        fail(f"{out}: cannot write the figure: {e}")
    print(f"wrote {out}")


def is_modeled(row):
    """A row of a modelling tracer (simt): its times are the GPU timing model's, not the CPU's wall time."""
    return row.get("modeled_ms", "") not in ("", None)


def cost_time(row, column="trace_ms"):
    """The time of a row for speed ratios, in ms. For a modelling tracer (simt: modeled_ms filled in) the modeled
    GPU time (trace: modeled_ms; end to end: modeled_e2e_ms), never its wall time; otherwise the measured column.
    Plots label such rows modeled."""
    if is_modeled(row):
        text = row.get("modeled_e2e_ms" if column == "e2e_ms" else "modeled_ms", "")
        return float(text) if text not in ("", None) else float("nan")
    return float(row[column]) if row.get(column, "") not in ("", None) else float("nan")
