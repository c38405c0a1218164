#!/usr/bin/env python3
"""Furniture on the real room frames of ../shared/data/real (the room graph, graphs/room.yaml),
judged against the labels a person wrote by looking at each colour image (room_labels.json, beside
this file: chairs, tables, sofas and doors, a loose box each; far, cut or unclear ones optional).

    python tests/bench/eval_room.py [--out DIR] [--json FILE]

Each accepted object is matched to the label of its class whose box holds the largest share of
its pixels (its parts' patches), at least 50%; a label is matched once. A match on a required
label is a true positive, on an optional one neither true nor false; an object matched to no label
is a false positive (furniture where there is none). Recall = required labels matched / required
labels (chairs and tables; sofas and doors apart). Prints one line per frame and the totals,
writes the overlays (objects drawn, label boxes in grey, optional ones dashed) to --out.
"""
from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
REAL = ROOT.parent / "shared" / "data" / "real"
LABELS = Path(__file__).with_name("room_labels.json")
MIN_SHARE = 0.5


def run(graph, frame):
    """The result dict of one frame and each segment's pixel indices."""
    from mereo import recognition

    r = graph.run([frame], keep=["result.result", "patches.segments"])[0]
    result = recognition._result(r, "skip")
    segments = {} if r["error"] else {s.id: np.asarray(s.pixels, np.int64) for s in r["outputs"]["patches.segments"]}
    return result, segments


def object_mask(obj: dict, segments: dict, shape) -> np.ndarray:
    m = np.zeros(shape, bool)
    for p in obj["parts"].values():
        if "segment" in p:
            m.reshape(-1)[segments.get(p["segment"], np.zeros(0, np.int64))] = True
    return m


def match(objects: list[dict], labels: list[dict], segments: dict, shape):
    """(object, label index or None, share) per accepted object, the largest objects first."""
    masks = [object_mask(o, segments, shape) for o in objects]
    order = sorted(range(len(objects)), key=lambda k: -masks[k].sum())
    used, out = set(), []
    for k in order:
        o, m = objects[k], masks[k]
        n = max(1, int(m.sum()))
        best, share = None, 0.0
        for i, t in enumerate(labels):
            if i in used or t["class"] != o["model"]:
                continue
            x0, y0, x1, y1 = t["box"]
            s = m[y0:y1 + 1, x0:x1 + 1].sum() / n
            if s > share:
                best, share = i, s
        if share < MIN_SHARE:
            best = None
        if best is not None:
            used.add(best)
        out.append((o, best, share))
    return out


def overlay(frame, result: dict, labels: list[dict], path: Path) -> None:
    import mereo
    from PIL import Image, ImageDraw

    img = Image.fromarray(mereo.recognition.draw_result(frame, result))
    d = ImageDraw.Draw(img)
    for t in labels:
        x0, y0, x1, y1 = t["box"]
        if t.get("optional"):
            for x in range(x0, x1, 8):
                d.line([(x, y0), (min(x + 4, x1), y0)], fill=(150, 150, 150))
                d.line([(x, y1), (min(x + 4, x1), y1)], fill=(150, 150, 150))
            for y in range(y0, y1, 8):
                d.line([(x0, y), (x0, min(y + 4, y1))], fill=(150, 150, 150))
                d.line([(x1, y), (x1, min(y + 4, y1))], fill=(150, 150, 150))
        else:
            d.rectangle(t["box"], outline=(200, 200, 200))
        d.text((x0 + 2, y1 - 12), t["class"], fill=(220, 220, 220))
    img.save(path)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", default="eval_room", help="overlays folder")
    ap.add_argument("--json", help="write the figures here")
    args = ap.parse_args(argv)
    if not REAL.is_dir():
        print(f"eval_room: {REAL} is missing (the shared data beside the clone); nothing to judge")
        return 0
    import mereo
    from mereo import recognition

    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    graph = recognition.tabletop_graph(graph="room")
    frames = json.loads(LABELS.read_text())["frames"]
    classes = ["chair", "table", "sofa", "door"]
    tp = {c: 0 for c in classes}
    need = {c: 0 for c in classes}
    fp = {c: 0 for c in classes}
    rows, times = [], []
    for fr in frames:
        frame = mereo.io.read(str(REAL / fr["path"]), **fr["read"])
        t0 = time.perf_counter()
        result, segments = run(graph, frame)
        times.append(1000 * (time.perf_counter() - t0))
        labels = fr["labels"]
        shape = np.asarray(frame.depth).shape[:2]
        objects = [o for o in result["objects"] if o["accepted"]]
        found, wrong = [], []
        matched = set()
        for o, i, share in match(objects, labels, segments, shape):
            if i is None:
                fp[o["model"]] = fp.get(o["model"], 0) + 1
                wrong.append(f"{o['model']} {o['score']:.2f}")
            else:
                matched.add(i)
                found.append(f"{o['model']}{' (optional)' if labels[i].get('optional') else ''}")
        missed = []
        for i, t in enumerate(labels):
            if t.get("optional"):
                continue
            need[t["class"]] += 1
            if i in matched:
                tp[t["class"]] += 1
            else:
                missed.append(t["class"])
        line = (f"{fr['name']:16s} found: {', '.join(found) or '-'}; missed: {', '.join(missed) or '-'}; "
                f"false: {', '.join(wrong) or '-'}")
        if result.get("warnings"):
            line += f" (warnings: {'; '.join(result['warnings'])})"
        print(line)
        rows.append({"frame": fr["name"], "found": found, "missed": missed, "false": wrong})
        overlay(frame, result, labels, out / f"{fr['name'].replace(' ', '_')}.png")
    print()
    for c in classes:
        print(f"{c:6s} recall {tp[c]}/{need[c]}, false {fp[c]}")
    cht = sum(tp[c] for c in ("chair", "table")), sum(need[c] for c in ("chair", "table"))
    accepted = sum(tp.values()) + sum(fp.values())
    print(f"chairs and tables: recall {cht[0]}/{cht[1]} = {cht[0] / max(1, cht[1]):.2f}; "
          f"furniture where there is none: {sum(fp.values())} objects")
    print(f"ms per frame (graph run, median): {np.median(times):.0f}; overlays in {out}")
    if args.json:
        Path(args.json).write_text(json.dumps({"frames": rows, "tp": tp, "need": need, "false": fp,
                                               "median_ms": float(np.median(times)), "accepted": accepted}, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
