"""scripts/check-results: run every check, print the mismatches and the coverage line; --self-test."""
import re
import sys
import time

from results_checks import (checks_denoise, checks_first_run, checks_generated, checks_gpu, checks_kernels, checks_l1,
                            checks_model, checks_ncu, checks_readme_converge, checks_readme_cwbvh,
                            checks_readme_gpu, checks_readme_model, checks_readme_quality, checks_readme_schema,
                            checks_scaling, checks_shard, checks_stage_counters, checks_stage_gpgpusim, checks_stage_l1,
                            checks_stage_latency, checks_stage_trips, checks_stages,
                            checks_top, checks_tune, coverage)
from results_checks.core import Embedded, Figure, Generated, Unrecorded, read_file, render, squash
from results_checks.rows import ROOT

MODULES = (checks_gpu, checks_first_run, checks_ncu, checks_kernels, checks_scaling, checks_stages, checks_stage_l1,
           checks_stage_trips, checks_stage_latency, checks_stage_counters, checks_stage_gpgpusim, checks_model,
           checks_tune, checks_top, checks_readme_converge, checks_readme_cwbvh, checks_readme_gpu,
           checks_readme_model, checks_readme_quality, checks_readme_schema, checks_shard, checks_denoise, checks_l1,
           checks_generated)
EXTRA_DOCS = ("results/shard-overhead.md",)  # hand-written documents that are not called README.md


def all_checks():
    return [c for m in MODULES for c in m.CHECKS]


def documents():
    found = sorted(str(p.relative_to(ROOT)) for p in (ROOT / "results").rglob("README.md"))
    return found + [d for d in EXTRA_DOCS if (ROOT / d).exists()]


def coverage_line(checks, passed):
    quoted = {}
    for c in checks:
        if isinstance(c, Figure) and c in passed:
            quoted.setdefault(c.readme, []).append(c.expected())
    figures = sum(1 for c in passed if isinstance(c, Figure) and not isinstance(c, Unrecorded))
    generated = sum(1 for c in passed if isinstance(c, Generated))
    docs = documents()
    checked = [d for d in docs if d in quoted]
    print(f"check-results: {len(checked)} of {len(docs)} hand-written results documents checked, {figures} quoted "
          f"figure texts recomputed from their rows, {generated} generated files made again by their scripts")
    unrecorded = {}
    for c in passed:
        if isinstance(c, Unrecorded):
            unrecorded[c.readme] = unrecorded.get(c.readme, 0) + len(coverage.uncovered(c.text, []))
    if unrecorded:
        print("check-results: figures quoted from no committed file (each README names where they come from): "
              + ", ".join(f"{d} {n}" for d, n in sorted(unrecorded.items())))
    open_docs = []
    for d in docs:
        left = coverage.uncovered(read_file(d), quoted.get(d, []))
        if left:
            open_docs.append((d, left))
    if open_docs:
        print("check-results: warning: figures that no check covers yet (count, first few):")
        for d, left in open_docs:
            print(f"  {d}: {len(left)} ({', '.join(left[:6])})")


def run(checks):
    failures, passed = [], []
    for c in checks:
        message = c.run(read_file)
        if message:
            failures.append(message)
        else:
            passed.append(c)
    return failures, passed


def alter_digit(text):
    """`text` with its last digit changed (the edit the self-test makes to a quoted figure)."""
    m = list(re.finditer(r"\d", text))
    if not m:
        return None
    i = m[-1].start()
    return text[:i] + str((int(text[i]) + 1) % 10) + text[i + 1:]


def self_test_embedded(check):
    """The README with a digit of its first copied table row edited; True when the check then fails."""
    line = next(line for line in check.lines() if re.search(r"\d", line))
    text = read_file(check.readme).replace(line, alter_digit(line))
    return check.run(lambda path: text if path == check.readme else read_file(path)) is not None


def self_test_figure(check):
    """The README with `check`'s figure edited in every place it is quoted; True when the check then fails."""
    if isinstance(check, Embedded):
        return self_test_embedded(check)
    if isinstance(check, Unrecorded):
        text = squash(read_file(check.readme)).replace(check.text, alter_digit(check.text))
        return check.run(lambda path: text if path == check.readme else read_file(path)) is not None
    values = check.value()
    values = values if isinstance(values, (tuple, list)) else (values,)
    want = render(check.text, values, check.minus)
    first = next((k for k, v in enumerate(values) if not isinstance(v, str)), 0)
    edited_values = list(values)
    edited_values[first] = alter_digit(render("{" + _spec(check.text, first) + "}", (values[first],), check.minus))
    edited = render(check.text, edited_values, check.minus)
    if edited == want:
        return True
    text = squash(read_file(check.readme)).replace(want, edited)
    return check.run(lambda path: text if path == check.readme else read_file(path)) is not None


def _spec(template, index):
    import string
    specs = [spec for _, name, spec, _ in string.Formatter().parse(template) if name is not None]
    return ":" + specs[index] if specs[index] else ""


def self_test_generated(check):
    text = read_file(check.output)
    lines = text.splitlines()
    k = next(i for i, line in enumerate(lines) if re.search(r"\d", line))
    lines[k] = alter_digit(lines[k])
    edited = "\n".join(lines) + "\n"
    return check.run(lambda path: edited if path == check.output else read_file(path)) is not None


def self_test(checks):
    """Every Figure check must fail on its README with the figure edited, and one generated file of each mode on
    its output with a digit edited."""
    bad = []
    for c in checks:
        if isinstance(c, Figure) and not self_test_figure(c):
            bad.append(c.describe())
    generated = [c for c in checks if isinstance(c, Generated)]
    for mode in ("equal", "lines"):
        c = next((g for g in generated if g.mode == mode), None)
        if c and not self_test_generated(c):
            bad.append(c.describe())
    if coverage.uncovered("within ±15%: 12 of 14 cells, 1.5× and 3% (`--k 0.5`)", []) != ["1.5", "3%"]:
        bad.append("coverage.py: a ±N% band, code or a result figure counted wrongly")
    levels = "the 95% interval, a 95% band, a 5% false-alarm rate at 32×8 × K 8: 4% of 2×"
    if coverage.uncovered(levels, []) != ["4%", "2×"]:
        bad.append("coverage.py: a confidence level or a size's second side counted as a figure")
    nominal = "above the nominal 5% of pixels, a nominal 2.5% each; 5% of pixels, 2.5% each"
    if coverage.uncovered(nominal, []) != ["5%", "2.5"]:
        bad.append("coverage.py: a test's nominal rate counted, or a share not named nominal skipped")
    if coverage.uncovered("## `x` CSV\n| `c` | σ = 1.5, |z| < 1.96, (r² + 0.01), ≥ 80%: 2.5% |\n## Results\nz = 1.5",
                          []) != ["2.5", "1.5"]:
        bad.append("coverage.py: a column definition's constant counted, or a result after = skipped")
    for b in bad:
        print(f"check-results --self-test: an edited figure passed: {b}")
    n = sum(isinstance(c, Figure) for c in checks)
    print(f"check-results --self-test: {n} figure checks and {min(2, len(generated))} generated files fail when "
          f"edited" if not bad else f"check-results --self-test: {len(bad)} checks do not notice an edit")
    return 1 if bad else 0


def main(argv):
    start = time.time()
    checks = all_checks()
    if argv and argv[0] == "--self-test":
        failures, _ = run(checks)
        if failures:
            print("check-results --self-test: the checks must pass first (run scripts/check-results)")
            return 1
        return self_test(checks)
    if argv:
        print("usage: scripts/check-results [--self-test]", file=sys.stderr)
        return 2
    failures, passed = run(checks)
    for f in failures:
        print(f"check-results: MISMATCH {f}")
    coverage_line(checks, passed)
    print(f"check-results: {len(failures)} mismatches ({time.time() - start:.1f} s)")
    return 1 if failures else 0
