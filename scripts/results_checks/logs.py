"""Reading the machine-readable logs a figure may come from: Nsight Compute's CSV output (`ncu --csv`, either the
section layout, one metric a line, or `--page raw`, one launch a line) and the `name  value` lines of the probe
and SASS-count text files.

Launches are numbered as ncu numbers them (its ID column, 0 the first profiled launch); a metric's value is read
as a number with its thousands separators dropped.
"""
import csv
import io
import lzma
import re

from results_checks.rows import ROOT, USED

_cache = {}


def _text(path):
    opener = lzma.open if path.endswith(".xz") else open
    with opener(ROOT / path, "rt", encoding="utf-8", errors="replace") as f:
        return f.read()


def ncu_rows(path):
    """The CSV rows of an ncu log (the lines that start with a quote), read once."""
    if path not in _cache:
        lines = [line for line in _text(path).splitlines() if line.startswith('"')]
        _cache[path] = list(csv.DictReader(io.StringIO("\n".join(lines))))
    USED.add(path)
    return _cache[path]


def number(text):
    return float(text.replace(",", ""))


def ncu(path, launch, metric):
    """The value of `metric` for launch `launch` of an ncu log: in the section layout the row whose 'Metric Name'
    is `metric`; in the raw layout the column `metric`. Raises when the log has none."""
    for row in ncu_rows(path):
        if row.get("ID") != str(launch):
            continue
        if "Metric Name" in row:
            if row["Metric Name"] == metric:
                return number(row["Metric Value"])
        elif metric in row:
            return number(row[metric])
    raise LookupError(f"{path}: no {metric!r} for launch {launch}")


def text_lines(path):
    USED.add(path)
    return _text(path).splitlines()


def sass_step(path, step, field):
    """A figure of a `scripts/count-cwbvh-step-instructions` output line: `step` is the line's first words
    ('tuned node_step'), `field` one of instructions, issue cycles, global loads, local accesses."""
    for line in text_lines(path):
        if line.startswith(step + " "):
            m = re.search(re.escape(field) + r"\s+(-?[\d.]+)", line)
            if m:
                return float(m.group(1))
    raise LookupError(f"{path}: no {field!r} on the {step!r} line")
