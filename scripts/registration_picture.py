#!/usr/bin/env python3
"""Draws docs/registration.png: NYU Depth v2's raw frame (../shared/data/real/open3d), its depth's
outlines on the colour image read as one camera and registered with the Kinect's calibration
(data/cameras/nyu_depth_v2_kinect.json), whole and a close-up.

    .venv/bin/python scripts/registration_picture.py [--out docs/registration.png]
"""
import argparse
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import mereo  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
NYU = ROOT.parent / "shared" / "data" / "real" / "open3d" / "NYU_depth.pgm"
CALIBRATION = ROOT / "data" / "cameras" / "nyu_depth_v2_kinect.json"


def outlines(depth):
    """The near side of each depth jump of more than 4%, two pixels wide."""
    d = np.asarray(depth)  # NaN (no depth) compares false: the view's border is no outline
    e = np.zeros(d.shape, bool)
    with np.errstate(invalid="ignore"):
        e[:, :-1] |= d[:, 1:] - d[:, :-1] > 0.04 * d[:, :-1]
        e[:, 1:] |= d[:, :-1] - d[:, 1:] > 0.04 * d[:, 1:]
        e[:-1, :] |= d[1:, :] - d[:-1, :] > 0.04 * d[:-1, :]
        e[1:, :] |= d[:-1, :] - d[1:, :] > 0.04 * d[1:, :]
    e &= np.isfinite(d)
    e[:, 1:] |= e[:, :-1]
    return e


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--out", default=str(ROOT / "docs" / "registration.png"))
    args = p.parse_args()
    if not NYU.is_file():
        raise SystemExit(f"{NYU} not found: the real frames are in ../shared beside the repository")
    one = mereo.io.read(NYU, intrinsics=mereo.io.read_intrinsics(str(CALIBRATION)), depth_format="nyu-raw")
    reg = mereo.io.read(NYU, intrinsics=CALIBRATION, depth_format="nyu-raw")
    fig, axes = plt.subplots(2, 2, figsize=(12, 9.6), gridspec_kw=dict(height_ratios=[1, 0.8]))
    crop = (slice(60, 260), slice(130, 380))
    for col, (f, title) in enumerate([(one, "read as one camera"), (reg, "registered to the colour camera")]):
        img = np.asarray(f.color).copy()
        img[outlines(f.depth)] = (255, 0, 255)
        axes[0, col].imshow(img)
        axes[0, col].add_patch(plt.Rectangle((crop[1].start, crop[0].start), 250, 200, fill=False, ec="yellow", lw=1.5))
        axes[0, col].set_title(f"NYU raw depth {title}")
        axes[1, col].imshow(img[crop])
        for a in axes[:, col]:
            a.set_xticks([]), a.set_yticks([])
    fig.tight_layout()
    fig.savefig(args.out, dpi=80)
    print(args.out)


if __name__ == "__main__":
    main()
