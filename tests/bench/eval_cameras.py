#!/usr/bin/env python3
"""Recognition on rendered frames that look like more cameras, both depth models, judged against
the renderer's exact ground truth.

    python tests/bench/eval_cameras.py [--first 5000] [--frames 50] [--depth-model kinect stereo]

Each frame: varied handles (torus, D-shaped, squared, band), lying cans and jars, free-form
distractors (blobs, bananas, drills, rounded boxes) and tapered cups. Prints `mereo evaluate`'s
table per depth model: precision and recall per model, recall by kind, accepted objects on the
distractors per frame. Seeds 5000-5049 were used for nothing else (the figures of issue 18).
Tapered cups are "tapered_cup" in the ground truth and in the shipped graph's models.
"""
from __future__ import annotations

import argparse
import sys


def main(argv=None) -> int:
    import mereo
    from mereo import evaluate as ev

    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--first", type=int, default=5000)
    ap.add_argument("--frames", type=int, default=50)
    ap.add_argument("--depth-model", nargs="+", default=["kinect", "stereo"])
    args = ap.parse_args(argv)
    seeds = [f"synthetic:{s}" for s in range(args.first, args.first + args.frames)]
    for model in args.depth_model:
        so = mereo.synthetic.SceneOptions()
        so.depth_model = model
        so.handle_shapes = "varied"
        so.lying_containers = True
        so.freeform_distractors = True
        so.tapered_cups = True
        results = mereo.recognize_all([mereo.io.read(s, scene=so) for s in seeds])
        e = ev.evaluate(results, ev.load_truths(seeds, options=so))
        print(f"== depth model {model}, {seeds[0]}..{seeds[-1]}")
        print(ev.format_table(e))
    return 0


if __name__ == "__main__":
    sys.exit(main())
