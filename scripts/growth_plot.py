#!/usr/bin/env python3
"""Draws docs/growth.png: how the tabletop pipeline's time per frame grows with the number of
objects on the table and with the image size, from the JSON line of `bench_pipeline --growth`.

    build/dev/tests/bench/bench_pipeline --growth > growth.txt
    .venv/bin/python scripts/growth_plot.py growth.txt [--out docs/growth.png]
"""
import argparse
import json

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

STAGES = ("filter", "normals", "table", "primitives")


def read(path):
    """The last line of the benchmark's output that is its JSON object."""
    for line in reversed(open(path).read().splitlines()):
        if line.startswith("{") and '"pipeline_growth"' in line:
            return json.loads(line)
    raise SystemExit(f"{path}: no JSON line of bench_pipeline --growth")


def panel(ax, rows, x, labels, xlabel):
    """Stacked stage medians (one frame at a time) and the whole frame's median."""
    bottom = [0.0] * len(rows)
    for st in STAGES:
        ms = [r["stage_median_ms"][st] for r in rows]
        ax.bar(x, ms, bottom=bottom, width=0.6, label=st)
        bottom = [b + m for b, m in zip(bottom, ms)]
    ax.bar(x, [max(0.0, r["median_ms"] - b) for r, b in zip(rows, bottom)], bottom=bottom, width=0.6, color="lightgrey",
           label="rest (matching, regions, result)")
    ax.plot(x, [1000.0 / r["fps"] for r in rows], "k.--", label="1000 / frames per second, parallel")
    ax.set_xticks(x, labels)
    ax.set_xlabel(xlabel)
    ax.set_ylabel("ms per frame")
    ax.grid(axis="y", alpha=0.3)


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("figures", help="the output of bench_pipeline --growth")
    p.add_argument("--out", default="docs/growth.png")
    args = p.parse_args()
    j = read(args.figures)
    fig, (a, b) = plt.subplots(1, 2, figsize=(11, 4.2), gridspec_kw={"width_ratios": [2, 1]})
    rows = j["objects"]
    panel(a, rows, range(len(rows)), [str(r["objects"]) for r in rows], "objects on the table (VGA)")
    rows = j["size"]
    panel(b, rows, range(len(rows)), [f'{r["width"]}x{r["height"]}' for r in rows], "image size (3-6 objects)")
    a.legend(fontsize=8, loc="upper left")
    fig.suptitle(f'bench_pipeline --growth: the tabletop graph, median of {j["frames_per_point"]} frames per point '
                 "(rendered, Kinect-like)", fontsize=10)
    fig.tight_layout()
    fig.savefig(args.out, dpi=90)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
