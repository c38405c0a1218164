#!/usr/bin/env python3
"""Recognition on the labelled real frames of ../shared/data/real, judged against their labels.

    python tests/bench/eval_real.py [--out DIR] [--json FILE]

  - nv-6dof-graspnet (RealSense-like, one object per frame, a pixel mask each): a frame passes when
    it reports exactly one accepted object, of the expected class, with at least 80% of its body's
    pixels inside the mask (a mug: also its handle part, with 80% of it in the mask).
  - posecnn (YCB objects, a box and a class for every object in labels.json): each accepted object
    is matched to the label box holding most of its pixels (at least 70% of them); it is a true
    positive when that label's class is compatible with the object's model (COMPATIBLE below).
    Precision = true positives / accepted objects; recall = labelled cans, bowls, bottles, mugs
    and pitchers (not 'difficult') with a true positive on them / all of those.

  - the real mugs (nv red_mug, PCL's stereo mug, the PoseCNN frames with a labelled mug): how many
    accepted mugs have a handle when it may be seen in the depth alone, with the colour silhouette,
    with the colour image's edges (HANDLE_SOURCES).

Prints one line per frame and the totals, writes the overlays (objects drawn, label boxes in
grey) to --out. An object's pixels are its parts' inlier pixels.
"""
from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
REAL = ROOT.parent / "shared" / "data" / "real"

POSECNN = dict(intrinsics="1066.778,1067.487,312.9869,241.3109", depth_scale=10000.0)
NV_EXPECTED = {"red_mug": "mug", "white_mug": "bowl", "white_bowl": "bowl", "green_bowl": "bowl",
               "cylinder": "can"}
# label classes a reported model may lie on: the model itself, and for a closed cylinder ("jar: a
# closed cylindrical jar or tin") a can; "container" is the general model of them all
COMPATIBLE = {"mug": {"mug"}, "cup": {"cup"}, "tapered_cup": {"cup"}, "can": {"can"}, "jar": {"jar", "can"},
              "bottle": {"bottle"}, "bowl": {"bowl"}, "plate": {"plate"}, "pitcher": {"pitcher"},
              "container": {"mug", "cup", "can", "jar", "bottle", "pitcher"}}
RECALL_CLASSES = {"can", "bowl", "bottle", "mug", "pitcher"}


class SegmentPixels:
    """Each segment's pixels as a mask of the frame (segments overlap: a region holds primitives)."""

    def __init__(self, segments, shape):
        self.shape = shape
        self.by_id = {s.id: np.asarray(s.pixels, np.int64) for s in segments}

    def of(self, seg_id: int) -> np.ndarray:
        m = np.zeros(self.shape, bool)
        m.reshape(-1)[self.by_id.get(seg_id, np.zeros(0, np.int64))] = True
        return m


def run(frame, **primitive_options):
    """The result dict and the segments' pixels of one frame (tabletop graph, deterministic; the
    options given set the detect_primitives node's)."""
    from mereo import recognition

    g = recognition.tabletop_graph()
    if primitive_options:
        g.set_options("primitives", **primitive_options)
    r = g.run([frame], keep=["result.result", "regions.segments"])[0]
    result = recognition._result(r, "skip")
    segments = [] if r["error"] else r["outputs"]["regions.segments"]
    return result, SegmentPixels(segments, np.asarray(frame.depth).shape[:2])


def part_pixels(labels: SegmentPixels, part: dict) -> np.ndarray:
    return labels.of(part["segment"]) if "segment" in part else np.zeros(labels.shape, bool)


def object_pixels(labels: SegmentPixels, obj: dict) -> np.ndarray:
    m = np.zeros(labels.shape, bool)
    for p in obj["parts"].values():
        m |= part_pixels(labels, p)
    return m


def accepted(result: dict) -> list[dict]:
    return [o for o in result["objects"] if o["accepted"]]


def eval_nv(name: str, result: dict, labels: SegmentPixels, mask: np.ndarray) -> tuple[bool, str]:
    objs = accepted(result)
    want = NV_EXPECTED[name]
    got = ", ".join(f"{o['model']} {o['score']:.2f}" for o in objs) or "nothing"
    if result.get("warnings"):
        got += f" (warnings: {'; '.join(result['warnings'])})"
    if len(objs) != 1 or objs[0]["model"] != want:
        return False, got
    o = objs[0]
    import mereo.evaluate

    body = part_pixels(labels, mereo.evaluate.body_part(o))
    inside = (body & mask).sum() / max(1, body.sum())
    text = f"{got}{' (' + o['modality'] + ')' if 'modality' in o else ''}, body {100 * inside:.0f}% in the mask"
    ok = inside >= 0.8
    if want == "mug":
        if "handle" not in o["parts"]:
            return False, text + ", no handle"
        handle = part_pixels(labels, o["parts"]["handle"])
        h_in = (handle & mask).sum() / max(1, handle.sum())
        text += f", handle {100 * h_in:.0f}% in the mask"
        ok &= h_in >= 0.8
    return ok, text


def match_posecnn(result: dict, labels: SegmentPixels, truth: list[dict]):
    """(model, label index or None, share of the object's pixels in that box) per accepted object."""
    out = []
    for o in accepted(result):
        px = object_pixels(labels, o)
        n = max(1, int(px.sum()))
        best, best_share = None, 0.0
        for i, t in enumerate(truth):
            x0, y0, x1, y1 = t["box"]
            share = px[y0:y1 + 1, x0:x1 + 1].sum() / n
            # the compatible label wins a tie with an incompatible one (boxes overlap)
            key = (share >= 0.7 and t["class"] in COMPATIBLE.get(o["model"], set()), share)
            if best is None or key > best_key:
                best, best_share, best_key = i, share, key
        if best_share < 0.7:
            best = None
        out.append((o, best, best_share))
    return out


def overlay(frame, result: dict, boxes: list[dict], path: Path) -> None:
    """The result drawn over the frame, with the label boxes in grey (dashed: "optional" ones)."""
    import mereo
    from PIL import Image, ImageDraw

    img = Image.fromarray(mereo.recognition.draw_result(frame, result))
    d = ImageDraw.Draw(img)
    grey = (160, 160, 160)
    for t in boxes:
        x0, y0, x1, y1 = t["box"]
        if t.get("optional"):
            for x in range(x0, x1, 8):
                d.line([(x, y0), (min(x + 4, x1), y0)], fill=grey)
                d.line([(x, y1), (min(x + 4, x1), y1)], fill=grey)
            for y in range(y0, y1, 8):
                d.line([(x0, y), (x0, min(y + 4, y1))], fill=grey)
                d.line([(x1, y), (x1, min(y + 4, y1))], fill=grey)
        else:
            d.rectangle(t["box"], outline=grey)
        d.text((x0 + 2, y1 - 12), t["class"], fill=(200, 200, 200))
    img.save(path)


# where a mug's handle may be seen: the depth's surfaces alone, and each colour modality beside them
HANDLE_SOURCES = {"depth": dict(handles_from_colour=False, handles_from_edges=False),
                  "colour silhouette": dict(handles_from_colour=True, handles_from_edges=False),
                  "edges": dict(handles_from_colour=False, handles_from_edges=True)}


def handle_sources(frame) -> str:
    """Which sources alone (beside the depth's surfaces) give the frame's accepted mugs a handle."""
    counts = {}
    for name, options in HANDLE_SOURCES.items():
        result, _ = run(frame, **options)
        counts[name] = sum(o["model"] == "mug" and "handle" in o["parts"] for o in accepted(result))
    return ", ".join(f"{name} {n}" for name, n in counts.items())


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", default=str(ROOT / "out" / "eval_real"), help="overlay folder")
    ap.add_argument("--json", help="write the figures to this file")
    args = ap.parse_args(argv)
    if not REAL.is_dir():
        print(f"skipped: {REAL} is not there (the shared data sits beside the repository)")
        return 0
    import mereo
    from PIL import Image

    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    figures: dict = {"nv": {}, "posecnn": {}}

    print("nv-6dof-graspnet (RealSense-like; one object, its pixel mask):")
    nv_pass = 0
    for name, want in NV_EXPECTED.items():
        base = REAL / "nv-6dof-graspnet" / name
        frame = mereo.io.read(str(base) + "-depth.png")  # camera_params.json beside it
        result, labels = run(frame)
        mask = np.asarray(Image.open(str(base) + "-mask.png").convert("L")) > 0
        ok, text = eval_nv(name, result, labels, mask)
        nv_pass += ok
        figures["nv"][name] = {"pass": bool(ok), "found": text}
        print(f"  {'PASS' if ok else 'fail'} {name:11s} want {want:5s} got {text}")
        overlay(frame, result, [], out / f"nv_{name}.png")
    print(f"  {nv_pass}/{len(NV_EXPECTED)} frames right")
    figures["nv_frames_right"] = nv_pass

    print("posecnn (YCB; labels.json):")
    labels_file = json.loads((REAL / "posecnn" / "labels.json").read_text())
    tp = fp = 0
    wanted = found = 0
    for fid, truth in sorted(labels_file["frames"].items()):
        frame = mereo.io.read(str(REAL / "posecnn" / f"{fid}-depth.png"), **POSECNN)
        result, labels = run(frame)
        matches = match_posecnn(result, labels, truth)
        hit = set()
        parts = []
        for o, i, share in matches:
            good = i is not None and truth[i]["class"] in COMPATIBLE.get(o["model"], set())
            tp += good
            fp += not good
            if good:
                hit.add(i)
            on = f"{truth[i]['class']} '{truth[i]['note'][:28]}'" if i is not None else f"no label ({100 * share:.0f}% in the best box)"
            parts.append(f"{o['model']} {o['score']:.2f} on {on}: {'ok' if good else 'WRONG'}")
        targets = [i for i, t in enumerate(truth) if t["class"] in RECALL_CLASSES and not t.get("difficult")]
        wanted += len(targets)
        found += len(hit & set(targets))
        missed = [truth[i]["class"] for i in targets if i not in hit]
        warn = f" warnings: {'; '.join(result['warnings'])}" if result.get("warnings") else ""
        print(f"  {fid}: {len(hit & set(targets))}/{len(targets)} labelled found; "
              f"{'; '.join(parts) or 'nothing accepted'}{'; missed ' + ', '.join(missed) if missed else ''}{warn}")
        figures["posecnn"][fid] = {"accepted": parts, "missed": missed}
        overlay(frame, result, truth, out / f"posecnn_{fid}.png")
    precision = tp / (tp + fp) if tp + fp else float("nan")
    recall = found / wanted if wanted else float("nan")
    print(f"  precision {tp}/{tp + fp} = {precision:.2f}; recall {found}/{wanted} = {recall:.2f}")
    figures.update(posecnn_precision=precision, posecnn_recall=recall, posecnn_tp=tp, posecnn_fp=fp,
                   posecnn_found=found, posecnn_wanted=wanted)
    # the real mugs: which source finds each one's handle (mugs with a handle, per source)
    print("mugs with a handle, by where the handle was seen (depth alone; with the colour silhouette; with edges):")
    mug_frames = {"nv-6dof-graspnet red_mug": (str(REAL / "nv-6dof-graspnet" / "red_mug-depth.png"), {}),
                  "pcl table_scene_mug_stereo_textured": (str(REAL / "pcl" / "table_scene_mug_stereo_textured.pcd"), {})}
    for fid, truth in sorted(labels_file["frames"].items()):
        if any(t["class"] == "mug" for t in truth):
            mug_frames[f"posecnn {fid}"] = (str(REAL / "posecnn" / f"{fid}-depth.png"), POSECNN)
    figures["handle_sources"] = {}
    for name, (path, kw) in mug_frames.items():
        text = handle_sources(mereo.io.read(path, **kw))
        figures["handle_sources"][name] = text
        print(f"  {name}: {text}")
    print(f"overlays in {out}")
    if args.json:
        Path(args.json).write_text(json.dumps(figures, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
