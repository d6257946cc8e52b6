#!/usr/bin/python3
"""Image crop montage (the paper's magnified hotspot regions) from PNG files, e.g. the reference and each
generator's render written by `raycoh quality --crop` or `raycoh render`.

Without --crop: the images side by side with their labels. With --crop x,y,w,h (pixels, y = 0 at the top, as
raycoh's --crop): a first row with the first image and the region outlined, then the region of every image
magnified (nearest neighbour). All images must have the same size when cropping.

usage: montage.py ref.png noopt.png ours.png --out montage.png [--labels reference,noopt,ours]
                  [--crop x,y,w,h] [--cols N] [--title TEXT]
"""
import argparse
import math
import os

import matplotlib.image as mpimg
import matplotlib.patches as patches

from plotlib import fail, plt, save


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("images", nargs="+", help="PNG images")
    ap.add_argument("--out", required=True, help="figure file (.png, .pdf, .svg)")
    ap.add_argument("--labels", help="comma-separated labels, one per image (default: file names)")
    ap.add_argument("--crop", help="x,y,w,h region to magnify")
    ap.add_argument("--cols", type=int, default=0, help="images per row (default: all in one row)")
    ap.add_argument("--title")
    a = ap.parse_args()

    labels = a.labels.split(",") if a.labels else [os.path.splitext(os.path.basename(p))[0] for p in a.images]
    if len(labels) != len(a.images):
        fail(f"--labels has {len(labels)} entries for {len(a.images)} images")
    images = []
    for p in a.images:
        if not os.path.isfile(p):
            fail(f"{p}: no such image file")
        if not p.lower().endswith(".png"):
            fail(f"{p}: montage reads PNG images (raycoh writes them with --out x.png or quality's images)")
        try:
            images.append(mpimg.imread(p))
        except (OSError, SyntaxError, ValueError) as e:
            fail(f"{p}: cannot read: {e}")
    crop = None
    if a.crop:
        try:
            crop = [int(v) for v in a.crop.split(",")]
        except ValueError:
            crop = []
        if len(crop) != 4 or crop[2] < 1 or crop[3] < 1 or crop[0] < 0 or crop[1] < 0:
            fail(f"--crop {a.crop}: expected x,y,w,h with w, h >= 1")
        for p, img in zip(a.images, images):
            h, w = img.shape[:2]
            if crop[0] + crop[2] > w or crop[1] + crop[3] > h:
                fail(f"--crop {a.crop} is not inside {p} ({w}x{h})")
    cols = a.cols if a.cols > 0 else len(images)
    rows = math.ceil(len(images) / cols) + (1 if crop else 0)
    fig, axes = plt.subplots(rows, cols, figsize=(3.2 * cols, 3.0 * rows), squeeze=False)
    for ax in axes.flat:
        ax.axis("off")
    start = 0
    if crop:
        ax = axes[0, 0]
        ax.imshow(images[0], interpolation="nearest")
        ax.add_patch(patches.Rectangle((crop[0] - 0.5, crop[1] - 0.5), crop[2], crop[3], fill=False,
                                       edgecolor="red", linewidth=1.5))
        ax.set_title(f"{labels[0]} (region {crop[0]},{crop[1]} {crop[2]}x{crop[3]})", fontsize=8)
        start = 1
    for i, (img, label) in enumerate(zip(images, labels)):
        ax = axes[start + i // cols, i % cols]
        if crop:
            img = img[crop[1]:crop[1] + crop[3], crop[0]:crop[0] + crop[2]]
        ax.imshow(img, interpolation="nearest")
        ax.set_title(label, fontsize=9)
    if a.title:
        fig.suptitle(a.title)
    fig.tight_layout()
    save(fig, a.out)


if __name__ == "__main__":
    main()
