#!/usr/bin/env python3
"""The intervals of records/speed_interval.h, recomputed in Python from a table's rows, number for number.

The summaries of a GPU run (scripts/stage_bounds.py, scripts/gpu_check_summary.py) state ratios and winners with the
same intervals the table and the report print: the median's order-statistic interval and the paired bootstrap of a
speed ratio (2000 resamples, SplitMix64 from the same seed, indices = next() mod n), as docs/statistics.md states.
tests/scripts_test.sh checks that this module and `raycoh report` print the same intervals for the same rows.

Usage as a script: scripts/speed_interval.py TABLE.csv [--e2e]
  prints, per scene and tracer, every method's ratio to noopt with its interval and the top of the ranking.
"""
import csv
import sys
from collections import defaultdict

from result_key import row_label

RESAMPLES = 2000
SEED = 0x5EED1E550FA11
CONFIDENCE = 0.95
MASK = (1 << 64) - 1


class SplitMix64:
    def __init__(self, seed):
        self.state = seed & MASK

    def next(self):
        self.state = (self.state + 0x9E3779B97F4A7C15) & MASK
        z = self.state
        z = ((z ^ (z >> 30)) * 0xBF58476D1CE4E5B9) & MASK
        z = ((z ^ (z >> 27)) * 0x94D049BB133111EB) & MASK
        return z ^ (z >> 31)

    def index(self, n):
        return self.next() % n


def median(values):
    v = sorted(values)
    h = len(v) // 2
    return v[h] if len(v) % 2 else 0.5 * (v[h - 1] + v[h])


def quantile(sorted_values, q):
    at = q * (len(sorted_values) - 1)
    i = int(at)
    if i + 1 >= len(sorted_values):
        return sorted_values[-1]
    return sorted_values[i] + (at - i) * (sorted_values[i + 1] - sorted_values[i])


def binomial_half_cdf(n, k):
    """P(B <= k) for B ~ Binomial(n, 1/2)."""
    p, term = 0.0, 0.5 ** n
    for i in range(k + 1):
        p += term
        term = term * (n - i) / (i + 1)
    return p


def median_interval(samples, confidence=CONFIDENCE):
    """(median, lo, hi, level): the order-statistic interval of median_interval in C++."""
    v = sorted(samples)
    n = len(v)
    if n == 0:
        return 0.0, 0.0, 0.0, 0.0
    m = median(v)
    if n == 1:
        return m, v[0], v[0], 0.0
    k = 1
    while k + 1 <= (n + 1) // 2 and 1.0 - 2.0 * binomial_half_cdf(n, k) >= confidence:
        k += 1
    return m, v[k - 1], v[n - k], 1.0 - 2.0 * binomial_half_cdf(n, k - 1)


def speed_ratio(base, method):
    """base, method: {frame: (times, rays)}. Returns (ratio, lo, hi, has_interval) as speed_ratio in C++."""
    frames = [f for f in sorted(base) if f in method and base[f][0] and method[f][0]]
    if not frames:
        return 0.0, 0.0, 0.0, False
    repeated = any(len(base[f][0]) > 1 or len(method[f][0]) > 1 for f in frames)

    def ratio_of(picked, draw):
        base_rays = base_t = method_rays = method_t = 0.0
        for f in picked:
            base_t += median(draw(base[f][0]))
            base_rays += base[f][1]
            method_t += median(draw(method[f][0]))
            method_rays += method[f][1]
        if base_t > 0 and method_t > 0 and base_rays > 0:
            return (method_rays / method_t) / (base_rays / base_t)
        return 0.0

    ratio = ratio_of(frames, lambda t: t)
    if not repeated:
        return ratio, ratio, ratio, False
    rng = SplitMix64(SEED)

    def draw(t):
        return [t[rng.index(len(t))] for _ in t]

    ratios = []
    for _ in range(RESAMPLES):
        picked = [frames[rng.index(len(frames))] if len(frames) > 1 else frames[0] for _ in frames]
        ratios.append(ratio_of(picked, draw))
    ratios.sort()
    return ratio, quantile(ratios, 0.5 * (1 - CONFIDENCE)), quantile(ratios, 0.5 * (1 + CONFIDENCE)), True


def ratio_text(r):
    ratio, lo, hi, has = r
    return f"{ratio:.2f}x [{lo:.2f}, {hi:.2f}]" if has else f"{ratio:.2f}x"


def verdict(r):
    ratio, lo, hi, has = r
    if not has:
        return "no interval"
    return "faster" if lo > 1 else "slower" if hi < 1 else "indistinguishable"


def _num(row, col):
    v = row.get(col, "")
    return float(v) if v not in ("", None) else None


def row_times(row, e2e):
    """A row's repeats (ms) as the table holds them: the samples column, else the median alone."""
    samples = row.get("e2e_samples_ms" if e2e else "trace_samples_ms", "")
    if samples:
        return [float(x) for x in samples.split(";")]
    if not e2e:
        return [float(row["trace_ms"])]
    span = _num(row, "gpu_e2e_ms")
    return [span if span is not None else float(row["e2e_ms"])]


def series(rows, e2e):
    """{frame: (times, rays)} of one method's rows (one tracer, one scene)."""
    return {int(r["frame"]): (row_times(r, e2e), float(r["rays"])) for r in rows}


def series_speed(s):
    rays = sum(rays for times, rays in s.values() if times)
    t = sum(median(times) for times, rays in s.values() if times)
    return rays / t if t > 0 else 0.0


def top_of_ranking(methods, base):
    """methods: [(label, series)]; base: noopt's series. The same words as top_of_ranking in C++."""
    if not methods:
        return ""
    best = 0
    for i in range(1, len(methods)):
        if series_speed(methods[i][1]) > series_speed(methods[best][1]):
            best = i
    label, top = methods[best]
    to_base = speed_ratio(base, top)
    if not to_base[3]:
        return f"{label} highest, {ratio_text(to_base)} (no repeated times in the rows: no interval, not called fastest)"
    # The base itself: its ratio to itself is 1 by definition, no interval.
    tied = "".join(f", {m} {'1.00x' if s is base else ratio_text(speed_ratio(base, s))}"
                   for i, (m, s) in enumerate(methods) if i != best and speed_ratio(s, top)[1] <= 1.0)
    top_ratio = "1.00x" if top is base else ratio_text(to_base)
    if not tied:
        return f"{label} fastest, {top_ratio}"
    return f"indistinguishable at the top: {label} {top_ratio}{tied}"


def main(argv):
    if len(argv) < 2:
        sys.exit(__doc__)
    e2e = "--e2e" in argv
    groups = defaultdict(lambda: defaultdict(list))
    with open(argv[1], newline="") as f:
        for r in csv.DictReader(f):
            if r.get("modeled_ms", "") == "":  # measured rows: the primary pass and every method
                groups[(r["scene"], row_label(r, every_parameter=True))][r["method"]].append(r)
    for (scene, tracer), by_method in groups.items():
        base = series(by_method["noopt"], e2e)
        print(f"{scene}, {tracer}:")
        for m, rows in by_method.items():  # noopt is the base: 1 by definition, no interval
            print(f"  {m}: " + ("1.00x" if m == "noopt" else ratio_text(speed_ratio(base, series(rows, e2e)))))
        ranked = [(m, series(rows, True)) for m, rows in by_method.items() if m != "primary"]
        print(f"  top: {top_of_ranking(ranked, dict(ranked)['noopt'])}")


if __name__ == "__main__":
    main(sys.argv)
