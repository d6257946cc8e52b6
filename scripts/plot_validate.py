#!/usr/bin/python3
"""The GPU timing model against the paper, from `raycoh validate`'s CSV (results/README.md, "validate").

Left: Table 1's Sibenik column, speedup over NoOpt per method, paper (measured on an RTX 3060) beside the model
(modeled, simt preset). Right: Table 3, speedup of `ours` over NoOpt against the group size K, one colour per
tile size, paper solid and model dashed. Every modeled figure is labelled modeled.

Usage: plot_validate.py validate.csv --out out.png
"""
import argparse

from plotlib import fail, footer, number, plt, read_csv, save


def main():
    ap = argparse.ArgumentParser(description="The GPU timing model against the paper (raycoh validate's CSV).")
    ap.add_argument("csv")
    ap.add_argument("--out", required=True)
    a = ap.parse_args()
    path, out = a.csv, a.out
    rows = read_csv(path, ["table", "row", "paper_row", "tile", "k", "paper_ratio", "modeled_ratio", "preset"])
    t1 = [r for r in rows if r["table"] == "table1" and r["paper_ratio"] not in ("", "nan")]
    t3 = [r for r in rows if r["table"] == "table3"]
    if not t1 or not t3:
        fail(f"{path}: needs table1 and table3 rows")
    preset = rows[0]["preset"]
    fig, (a, b) = plt.subplots(1, 2, figsize=(12, 4.2))

    x = range(len(t1))
    a.bar([i - 0.2 for i in x], [number(r, "paper_ratio") for r in t1], 0.4, label="paper (RTX 3060, measured)",
          color="#4c72b0")
    a.bar([i + 0.2 for i in x], [number(r, "modeled_ratio") for r in t1], 0.4, label=f"model ({preset}, modeled)",
          color="#dd8452")
    a.set_xticks(list(x))
    a.set_xticklabels([r["paper_row"] for r in t1], rotation=30, ha="right")
    a.axhline(1.0, color="grey", lw=0.8)
    a.set_ylabel("speedup over NoOpt (trace only)")
    a.set_title("Table 1, Sibenik, 1920x1080")
    a.legend(frameon=False)

    tiles = sorted({r["tile"] for r in t3}, key=lambda t: [int(v) for v in t.split("x")])
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for i, tile in enumerate(tiles):
        cells = sorted((r for r in t3 if r["tile"] == tile), key=lambda r: int(r["k"]))
        ks = [int(r["k"]) for r in cells]
        c = colours[i % len(colours)]
        b.plot(ks, [number(r, "paper_ratio") for r in cells], "-o", color=c, label=f"{tile} paper")
        b.plot(ks, [number(r, "modeled_ratio") for r in cells], "--s", color=c, label=f"{tile} modeled")
    b.set_xscale("log", base=2)
    b.set_xticks([8, 16, 32, 64])
    b.set_xticklabels(["8", "16", "32", "64"])
    b.set_xlabel("group size K")
    b.set_ylabel("speedup of ours over NoOpt")
    b.set_title("Table 3, Sibenik: paper (solid) vs model (dashed, modeled)")
    b.legend(frameon=False, ncol=2, fontsize=8)
    footer(fig, rows)
    save(fig, out)


if __name__ == "__main__":
    main()
