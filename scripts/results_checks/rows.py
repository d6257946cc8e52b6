"""Reading committed CSV rows for the checks: load a file once, select rows, sum over frames, form ratios.

Speeds are summed as gpu_check_summary.py does (total rays / total time over the frames of a cell); a ratio to
noopt always takes noopt from the same file as the method (two files of one run are two measurements).
"""
import csv
import importlib.util
import math
import pathlib
import statistics

ROOT = pathlib.Path(__file__).resolve().parents[2]
_spec = importlib.util.spec_from_file_location("gpu_check_summary", ROOT / "scripts" / "gpu_check_summary.py")
_summary = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(_summary)
tracer_label = _summary.tracer_label  # cuda, cuda:counters, cuda:cwbvh, cuda:cwbvh-shared, simt, simt:cwbvh, ...

_cache = {}
USED = set()  # every CSV a check has read (the coverage line counts them)


def load(path):
    """The rows of a CSV under the repository root, read once."""
    if path not in _cache:
        with open(ROOT / path, newline="") as f:
            _cache[path] = list(csv.DictReader(f))
    USED.add(path)
    return _cache[path]


def method_of(row):
    return "primary" if row.get("pass") == "primary" else row["method"]


def select(path, scene=None, method=None, tracer=None, **columns):
    """Rows of `path` whose scene, method label ('primary' for the camera pass), tracer label and the given
    columns match; raises when none does (a check naming rows that do not exist is a broken check)."""
    out = [r for r in load(path)
           if (scene is None or r["scene"] == scene) and (method is None or method_of(r) == method)
           and (tracer is None or tracer_label(r) == tracer)
           and all(r.get(k) == v for k, v in columns.items())]
    if not out:
        raise LookupError(f"{path}: no row with scene={scene} method={method} tracer={tracer} {columns}")
    return out


def num(text):
    return float(text) if text not in (None, "") else math.nan


def total(path, field, scene=None, method=None, tracer="cuda", **columns):
    """A column summed over the selected rows (frames)."""
    return sum(num(r[field]) for r in select(path, scene, method, tracer, **columns))


def rate(path, scene, method, tracer="cuda", field="trace_ms", **columns):
    """MRay/s: total rays / total `field` milliseconds / 1000 (trace_ms, gpu_e2e_ms, modeled_ms, modeled_e2e_ms)."""
    rows = select(path, scene, method, tracer, **columns)
    return sum(num(r["rays"]) for r in rows) / sum(num(r[field]) for r in rows) / 1000.0


def modeled_field(field):
    return {"trace_ms": "modeled_ms", "gpu_e2e_ms": "modeled_e2e_ms"}.get(field, field)


def speedup(path, scene, method, tracer="cuda", field="trace_ms", base="noopt", **columns):
    """`method`'s speed over `base`'s in the same file, same tracer (simt: its modeled column of `field`)."""
    if tracer.startswith("simt"):
        field = modeled_field(field)
    return rate(path, scene, method, tracer, field, **columns) / rate(path, scene, base, tracer, field, **columns)


def median(values):
    return statistics.median(values)


def lo_hi(values):
    """(smallest, largest): a range quoted as 'a–b'."""
    values = list(values)
    return (min(values), max(values))


def pct(a, b):
    """a / b - 1."""
    return a / b - 1.0


WORDS = ("zero", "one", "two", "three", "four", "five", "six", "seven", "eight", "nine", "ten", "eleven", "twelve")


def word(n):
    """A count as the README writes it in prose ('ten')."""
    return WORDS[n] if 0 <= n < len(WORDS) else str(n)
