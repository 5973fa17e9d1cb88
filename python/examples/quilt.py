#!/usr/bin/env python3
"""Render a 3x3 quilt of the default scene (or of the model files given) with mvr and show its
views and the composed quilt with matplotlib. Without a display the figure goes to a PNG.

    python3 python/examples/quilt.py [MODEL...] [--out quilt-views.png]
"""
import argparse
import os

import matplotlib

if not os.environ.get("DISPLAY") and not os.environ.get("WAYLAND_DISPLAY"):
    matplotlib.use("Agg")  # no display: draw into a file
import matplotlib.pyplot as plt

import mvr


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("models", nargs="*", help="model files (default: the built-in scene)")
    parser.add_argument("--out", default="quilt-views.png", help="figure file without a display")
    parser.add_argument("--size", default="320x240", help="size of one view, WxH")
    args = parser.parse_args()

    r = mvr.render(args.models, view_grid=(3, 3), size=args.size, format="quilt")
    print(f"{r.scene}: {len(r)} views of {r.size[0]}x{r.size[1]} by {r.backend}:{r.method}")
    print(f"rig: {r.rig['kind']} {r.rig['columns']}x{r.rig['rows']}, "
          f"interaxial {r.rig['interaxial']:.4g}, convergence {r.rig['convergence']:.4g}")
    if r.comfort:
        print(r.comfort["text"])

    fig = plt.figure(figsize=(12, 6), layout="constrained")
    left, right = fig.subfigures(1, 2, width_ratios=[1, 1])
    axes = left.subplots(3, 3)
    for v, ax in enumerate(axes.flat):  # views left to right, top to bottom
        ax.imshow(r.color[v])
        ax.set_title(f"view {v}", fontsize=8)
        ax.axis("off")
    left.suptitle("the 9 views")
    ax = right.subplots()
    ax.imshow(r.composites["quilt"])
    ax.set_title("mvr.compose('quilt', ...)")
    ax.axis("off")

    if matplotlib.get_backend().lower() == "agg":
        fig.savefig(args.out, dpi=100)
        print(f"wrote {args.out}")
    else:
        plt.show()


if __name__ == "__main__":
    main()
