#!/usr/bin/python3
"""Markdown summary of the GPU timing model's figures in `raycoh table` CSVs: per scene and resolution, the
modeled NoOpt MRay/s and every method's modeled ratio to it (trace only and end to end). All figures are
MODELED (simt rows only); rows of other tracers are ignored.

Usage: model_summary.py table.csv [table.csv ...] [--out summary.md]
"""
import argparse
from collections import defaultdict

from plotlib import fail, is_modeled, number, read_csv


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("csv", nargs="+")
    ap.add_argument("--out", help="write the Markdown here instead of stdout")
    a = ap.parse_args()
    rows = read_csv(a.csv, ["scene", "method", "width", "height", "rays", "modeled_ms", "modeled_e2e_ms"])
    sums = defaultdict(lambda: [0.0, 0.0, 0.0])  # (scene, res, method) -> rays, modeled ms, modeled e2e ms
    methods, panels = [], []
    for r in rows:
        if not is_modeled(r):
            continue
        res = f"{r['width']}x{r['height']}"
        key = (r["scene"], res, r["method"])
        s = sums[key]
        s[0] += number(r, "rays")
        s[1] += number(r, "modeled_ms")
        e2e = number(r, "modeled_e2e_ms")
        s[2] += e2e if e2e == e2e else 0.0
        if r["method"] not in methods:
            methods.append(r["method"])
        if (r["scene"], res) not in panels:
            panels.append((r["scene"], res))
    if not sums:
        fail("no simt rows (modeled_ms empty everywhere)")
    if "noopt" not in methods:
        fail("no noopt rows: ratios are to the noopt baseline")
    out = ["| scene | resolution | modeled NoOpt MRay/s | " + " | ".join(m for m in methods if m != "noopt") + " |",
           "|---|---|---:|" + "---:|" * (len(methods) - 1)]
    scenes = list(dict.fromkeys(p[0] for p in panels))
    pixels = lambda res: int(res.split("x")[0]) * int(res.split("x")[1])  # noqa: E731
    panels.sort(key=lambda p: (scenes.index(p[0]), pixels(p[1])))
    for scene, res in panels:
        base = sums[(scene, res, "noopt")]
        cells = []
        for m in methods:
            if m == "noopt":
                continue
            s = sums.get((scene, res, m))
            if not s or s[1] <= 0:
                cells.append("—")
                continue
            trace = (s[0] / s[1]) / (base[0] / base[1])
            e2e = (s[0] / s[2]) / (base[0] / base[2]) if s[2] > 0 and base[2] > 0 else float("nan")
            cells.append(f"{trace:.2f}x" + (f" ({e2e:.2f}x e2e)" if m != "primary" else ""))
        out.append(f"| {scene} | {res} | {base[0] / base[1] * 1e-3:.0f} | " + " | ".join(cells) + " |")
    text = "\n".join(out) + "\n"
    if a.out:
        with open(a.out, "w") as f:
            f.write(text)
        print(f"wrote {a.out}")
    else:
        print(text, end="")


if __name__ == "__main__":
    main()
