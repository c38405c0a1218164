"""Edge-cylinders on rendered frames (issue 20, point 1): the edge modality's bodies, matched from
the colour image's lines and arcs alone by the `edge_cylinder` model (graphs/models/edges.yaml).

Of the cylindrical bodies (mugs, cups, jars, cans, bottles, plates) showing at least 500 pixels,
the share with an edge_cylinder hypothesis of score >= 0.5 whose parts (rim and sides, or rim and
base: the model's two modalities) lie on the object (at least 60% of each part's pixels within 3
pixels of the object's), and how many each modality found; and the hypotheses that lie on no
such object. No depth is used (the primitives are not lifted).

    python tests/bench/eval_edge_cylinders.py [--first 9500] [--frames 20] [--min-pixels 500]
"""
from __future__ import annotations

import argparse
import json
import sys
import time


def main(argv=None) -> int:
    import numpy as np
    import mereo

    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--first", type=int, default=9500, help="first seed (9500-9549: used for nothing else)")
    ap.add_argument("--frames", type=int, default=20)
    ap.add_argument("--min-pixels", type=int, default=500)
    args = ap.parse_args(argv)

    kb = mereo.knowledge.load_models()
    bodies = found = hypotheses = stray = 0
    by_modality = {}  # modality -> bodies it found
    ms = []
    for seed in range(args.first, args.first + args.frames):
        o = mereo.synthetic.SceneOptions()
        o.handle_shapes = "varied"
        sf = mereo.synthetic.render(seed, o)
        truth = json.loads(sf.truth_json())
        t0 = time.perf_counter()
        segs = mereo.features.detect_edge_primitives(np.asarray(sf.frame.color))  # colour only
        lattice = mereo.knowledge.recognize(kb, ["edge_cylinder"], segs, best=50)
        ms.append(1000 * (time.perf_counter() - t0))
        labels = np.asarray(sf.truth.objects)
        near = {}  # object id -> (model, visible body pixels, its pixels widened by 3)
        for ob in truth["objects"]:
            body = [p for p in ob["parts"] if p["role"] == "body" and p["class"] in ("cylinder", "cone")]
            if body:
                grown = _dilate(labels == ob["id"], 3)
                near[ob["id"]] = (ob["model"], body[0]["visible_pixels"], grown.ravel())
        hit = set()
        hit_by = {}
        for h in lattice.hypotheses:
            if h.score < 0.5:
                continue
            hypotheses += 1
            on = [k for k, (_, _, m) in near.items() if all(m[segs[i].pixels].mean() >= 0.6 for i in h.assignment if i >= 0)]
            stray += not on
            hit.update(on)
            hit_by.setdefault(h.modality, set()).update(on)
        for k, (model, visible, _) in near.items():
            if visible >= args.min_pixels:
                bodies += 1
                found += k in hit
                for m, ks in hit_by.items():
                    by_modality[m] = by_modality.get(m, 0) + (k in ks)
                if k not in hit:
                    print(f"  seed {seed}: {model} ({visible} px) has no edge-cylinder")
    print(f"seeds {args.first}-{args.first + args.frames - 1}: edge-cylinders on {found}/{bodies} bodies of "
          f">= {args.min_pixels} px ({found / max(1, bodies):.2f}); {hypotheses} hypotheses >= 0.5, {stray} on no "
          f"cylindrical object; edges and matching {np.median(ms):.1f} ms a frame (median)")
    print("bodies found by each modality: " + ", ".join(f"{m} {n}" for m, n in sorted(by_modality.items())))
    return 0


def _dilate(mask, r):
    """mask widened by r pixels (a square window), with NumPy only."""
    import numpy as np

    out = mask.copy()
    for dy in range(-r, r + 1):
        for dx in range(-r, r + 1):
            out |= np.roll(np.roll(mask, dy, 0), dx, 1)
    return out


if __name__ == "__main__":
    sys.exit(main())
