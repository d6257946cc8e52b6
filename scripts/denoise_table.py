#!/usr/bin/python3
"""The table of results/denoise/README.md from `raycoh converge --denoise oidn` CSVs (one per scene and seed).

Per scene, method and frame count: the ratio of the method's relMSE to noopt's (same scene, seed and frame count),
raw and denoised, as the geometric mean over seeds with the smallest and largest seed's ratio; the change
denoised / raw (> 1: denoising moves the method's error further above noopt's, i.e. widens its gap or erases its
lead; < 1: closes the gap); the excess over noopt's relMSE (method - noopt, mean over seeds), raw and denoised: an
excess that stays while noopt's error falls is error the denoiser keeps (bias, or structure it takes for signal);
and the denoiser check (noopt's denoised relMSE below its raw one).
By default the ratios are taken on the reference-noise-corrected columns (rel_mse_corr, denoised_rel_mse_corr: the
reference's own noise is one constant in every error, and a large share of a denoised error at 128 frames);
--uncorrected takes rel_mse and denoised_rel_mse.

Usage: scripts/denoise_table.py results/denoise/converge_*_seed*.csv [--frames 1,4,16,128] [--uncorrected]
"""
import argparse
import collections
import csv
import math
import sys


def fail(msg):
    print(f"denoise_table.py: error: {msg}", file=sys.stderr)
    sys.exit(2)


def read(paths, raw_col, dn_col):
    # (scene, method, seed, frame) -> (raw, denoised); methods in first-seen order per scene.
    data, methods, seeds = {}, collections.OrderedDict(), collections.defaultdict(set)
    for path in paths:
        if path.endswith("-summary.csv"):
            continue
        try:
            rows = list(csv.DictReader(open(path, newline="")))
        except OSError as e:
            fail(f"{path}: {e.strerror}")
        for r in rows:
            for c in ("scene", "method", "seed", "frame", raw_col, dn_col):
                if c not in r:
                    fail(f"{path}: no column {c} (a converge CSV of --denoise oidn is needed)")
            if not r[dn_col]:
                continue
            key = (r["scene"], r["method"], int(r["seed"]), int(r["frame"]))
            data[key] = (float(r[raw_col]), float(r[dn_col]))
            methods.setdefault(r["scene"], [])
            if r["method"] not in methods[r["scene"]]:
                methods[r["scene"]].append(r["method"])
            seeds[r["scene"]].add(int(r["seed"]))
    return data, methods, seeds


def gmean(xs):
    return math.exp(sum(math.log(x) for x in xs) / len(xs))


def cell(xs):
    return f"{gmean(xs):.2f} ({min(xs):.2f}–{max(xs):.2f})" if len(xs) > 1 else f"{xs[0]:.2f}"


def verdict_of(change):
    """widens / closes when the geometric mean moves more than 5%, with whether every seed agrees; else about the
    same."""
    g = gmean(change)
    if 1 / 1.05 <= g <= 1.05:
        return "about the same"
    word = "widens" if g > 1 else "closes"
    agree = min(change) > 1 if g > 1 else max(change) < 1
    return f"{word} ({'one seed' if len(change) == 1 else 'every seed' if agree else 'not every seed'})"


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("csv", nargs="+")
    ap.add_argument("--frames", default="1,4,16,128")
    ap.add_argument("--uncorrected", action="store_true")
    a = ap.parse_args()
    frames = [int(f) for f in a.frames.split(",")]
    raw_col, dn_col = ("rel_mse", "denoised_rel_mse") if a.uncorrected else ("rel_mse_corr", "denoised_rel_mse_corr")
    data, methods, seeds = read(a.csv, raw_col, dn_col)
    if not data:
        fail("no denoised rows in the given files")
    print(f"relMSE ratio to noopt ({raw_col}, {dn_col}): geometric mean over seeds (lowest–highest seed)\n")
    for scene, ms in methods.items():
        ss = sorted(seeds[scene])
        print(f"### {scene} (seeds {', '.join(map(str, ss))})\n")
        print("| method | frames | raw ratio | denoised ratio | denoised / raw | verdict | excess raw / denoised |")
        print("|---|---:|---:|---:|---:|---|---:|")
        for f in frames:
            base = {s: data.get((scene, "noopt", s, f)) for s in ss}
            if any(v is None for v in base.values()):
                continue
            check = [base[s][1] / base[s][0] for s in ss]
            noopt = sum(base[s][0] for s in ss) / len(ss), sum(base[s][1] for s in ss) / len(ss)
            print(f"| noopt denoised / raw | {f} | | | {cell(check)} | "
                  f"{'denoiser lowers the error' if max(check) < 1 else 'NOT below raw for every seed'} | "
                  f"noopt {noopt[0]:.3g} / {noopt[1]:.3g} |")
            for m in ms:
                if m == "noopt":
                    continue
                pairs = [(data[(scene, m, s, f)], base[s]) for s in ss if (scene, m, s, f) in data]
                if not pairs:
                    continue
                raw = [v[0] / b[0] for v, b in pairs]
                dn = [v[1] / b[1] for v, b in pairs]
                change = [d / r for d, r in zip(dn, raw)]
                verdict = verdict_of(change)
                ex = [sum(v[i] - b[i] for v, b in pairs) / len(pairs) for i in (0, 1)]
                ex = [0.0 if abs(x) < 1e-12 else x for x in ex]  # float sums of equal errors
                print(f"| {m} | {f} | {cell(raw)} | {cell(dn)} | {cell(change)} | {verdict} | "
                      f"{ex[0]:+.3g} / {ex[1]:+.3g} |")
        print()


if __name__ == "__main__":
    main()
