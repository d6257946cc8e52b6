#!/usr/bin/python3
"""Tile size x group size heatmap (the paper's Table 3) from a `raycoh sweep` CSV.

Rows of the secondary pass whose generator is ours or contiguous (tile, its old name) are placed by the tile (W x H) and group size K of
their typed columns tile_w, tile_h and k; each cell is sum(rays) / sum(trace_ms) over frames, shown as the
ratio to noopt on the same scene and tracer (--value speedup, the default) or in MRay/s (--value mray).
One panel per scene and tracer. Cells the sweep did not run (K larger than the tile) stay empty.

usage: plot_sweep.py sweep.csv --out heatmap.png [--value speedup|mray] [--tracer NAME]
"""
import argparse
import textwrap
from collections import defaultdict

import numpy as np

from plotlib import TRACER_COLUMNS, cost_time, fail, footer, is_modeled, number, plt, read_csv, save, tracer_label


def tile_key(tile):
    w, _, h = tile.partition("x")
    try:
        return (int(w) * int(h), int(w), int(h))
    except ValueError:
        return (0, 0, 0)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("csv", nargs="+", help="CSV files written by raycoh sweep")
    ap.add_argument("--out", required=True, help="figure file (.png, .pdf, .svg)")
    ap.add_argument("--value", choices=["speedup", "mray"], default="speedup")
    ap.add_argument("--tracer", help="only this tracer (name)")
    a = ap.parse_args()

    rows = read_csv(a.csv, ["scene", "pass", "method", "generator", "tile_w", "tile_h", "k", "tracer", "rays",
                            "trace_ms"] + TRACER_COLUMNS)
    sums = defaultdict(lambda: [0.0, 0.0])  # (scene, tracer, tile, k) -> [rays, ms]; tile "noopt" for the baseline
    panels, used_rows = [], []
    for r in rows:
        if r["pass"] != "secondary" or (a.tracer and r["tracer"] != a.tracer):
            continue
        t = cost_time(r)
        if not (t > 0):
            continue
        if r["generator"] == "noopt" and r.get("encoder", "none") in ("", "none"):
            tile, k = "noopt", 0
        elif r["generator"] in ("ours", "contiguous", "tile"):
            if not (r["tile_w"] and r["tile_h"] and r["k"]):
                fail(f"method {r['method']}: its rows have no tile_w, tile_h or k")
            tile, k = f"{r['tile_w']}x{r['tile_h']}", int(r["k"])
        else:
            continue
        panel = (r["scene"], tracer_label(r) + (" (modeled)" if is_modeled(r) else " (measured)"))
        used_rows.append(r)
        if panel not in panels:
            panels.append(panel)
        sums[panel + (tile, k)][0] += number(r, "rays")
        sums[panel + (tile, k)][1] += t
    if not panels:
        fail("no secondary-pass rows of ours/contiguous" + (f" for tracer {a.tracer}" if a.tracer else ""))

    fig, axes = plt.subplots(1, len(panels), figsize=(5.2 * len(panels), 4.2), squeeze=False)
    for ax, panel in zip(axes[0], panels):
        tiles = sorted({key[2] for key in sums if key[:2] == panel and key[2] != "noopt"}, key=tile_key)
        ks = sorted({key[3] for key in sums if key[:2] == panel and key[2] != "noopt"})
        if not tiles:
            fail(f"scene {panel[0]}, tracer {panel[1]}: no ours/contiguous rows")
        base = sums.get(panel + ("noopt", 0))
        if a.value == "speedup" and not base:
            fail(f"scene {panel[0]}, tracer {panel[1]}: no noopt rows for the speedup (use --value mray)")
        grid = np.full((len(tiles), len(ks)), np.nan)
        for i, tile in enumerate(tiles):
            for j, k in enumerate(ks):
                cell = sums.get(panel + (tile, k))
                if cell and cell[1] > 0:
                    mray = cell[0] / cell[1] * 1e-3
                    grid[i, j] = mray / (base[0] / base[1] * 1e-3) if a.value == "speedup" else mray
        im = ax.imshow(np.ma.masked_invalid(grid), cmap="viridis", aspect="auto")
        for i in range(len(tiles)):
            for j in range(len(ks)):
                if np.isfinite(grid[i, j]):
                    bright = im.norm(grid[i, j]) > 0.6  # viridis turns yellow: dark text there
                    ax.text(j, i, f"{grid[i, j]:.2f}", ha="center", va="center",
                            color="black" if bright else "white", fontsize=8)
        ax.set_xticks(range(len(ks)), [f"K={k}" for k in ks])
        ax.set_yticks(range(len(tiles)), [f"({t.replace('x', ',')})" for t in tiles])
        ax.set_xlabel("group size K")
        ax.set_ylabel("tile (W,H)")
        ax.set_title(textwrap.fill(f"{panel[0]}, {panel[1]}", 40), fontsize=9)
        fig.colorbar(im, ax=ax, label="speedup over noopt" if a.value == "speedup" else "MRay/s")
    fig.tight_layout()
    footer(fig, used_rows)
    save(fig, a.out)


if __name__ == "__main__":
    main()
