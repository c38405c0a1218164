#!/usr/bin/env python3
"""Furniture on the real room frames of ../shared/data/real (the room graph, graphs/room.yaml),
judged against the labels a person wrote by looking at each colour image (room_labels.json, beside
this file: chairs, tables, sofas, doors and cabinets, a loose box each; far, cut or unclear ones optional);
with --rendered N, on N rendered rooms (SceneOptions(room=True), seeds from --first) against their
exact ground truth.

    python tests/bench/eval_room.py [--out DIR] [--json FILE]
    python tests/bench/eval_room.py --rendered 50 [--first 9100] [--depth-model stereo]

Rendered rooms: an accepted object is the truth object holding most of its pixels (the truth's
label image), a true positive when of the same model (each truth object once). Recall counts the
chairs, tables, doors and cabinets at least 40% visible (visible pixels over the pixels each would cover
with nothing in front of it, times the share of its projected box inside the image), precision
every accepted object. Size errors of the true positives: a table's top and a chair's seat, a door's
leaf, a cabinet's face, its longer and shorter side apart, over the parts at least 90% visible
themselves (their own share, as the object's above: a seat seen from behind is hidden by its own
back, and its depth is not seen to be measured).

Each accepted object is matched to the label of its class whose box holds the largest share of
its pixels (its parts' patches), at least 50%; a label is matched once. A match on a required
label is a true positive, on an optional one neither true nor false; an object matched to no label
is a false positive (furniture where there is none). Recall = required labels matched / required
labels (chairs and tables; sofas, doors and cabinets apart). Prints one line per frame and the totals,
writes the overlays (objects drawn, label boxes in grey, optional ones dashed) to --out.
"""
from __future__ import annotations

import argparse
import functools
import json
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
REAL = ROOT.parent / "shared" / "data" / "real"
LABELS = Path(__file__).with_name("room_labels.json")
MIN_SHARE = 0.5


def room_graph(settings=()):
    """The shipped room graph with NODE.OPTION=VALUE settings applied."""
    from mereo import recognition

    g = recognition.tabletop_graph(graph="room")
    for item in settings:
        key, value = item.split("=", 1)
        node, option = key.split(".", 1)
        try:
            v = int(value)
        except ValueError:
            try:
                v = float(value)
            except ValueError:
                v = value
        g.set_options(node, **{option: v})
    return g


def run(graph, frame):
    """The result dict of one frame and each segment's pixel indices."""
    from mereo import recognition

    r = graph.run([frame], keep=["result.result", "legs.segments"])[0]
    result = recognition._result(r, "skip")
    segments = {} if r["error"] else {s.id: np.asarray(s.pixels, np.int64) for s in r["outputs"]["legs.segments"]}
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


@functools.cache
def _eval_real():
    """eval_real.py beside this file, loaded once."""
    import importlib.util

    spec = importlib.util.spec_from_file_location("eval_real", Path(__file__).with_name("eval_real.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def overlay(frame, result: dict, labels: list[dict], path: Path) -> None:
    """eval_real.py's overlay: the result drawn, the label boxes in grey (optional ones dashed)."""
    _eval_real().overlay(frame, result, labels, path)


FURNITURE = ("chair", "table", "door", "cabinet")
NOT_FURNITURE = ("box",)  # room.yaml's boxes on stands and desks: neither judged nor false
# the renderer's kinds of table and the specializations of room.yaml that name them
SPECIALIZED = {("table", "coffee"): "coffee_table", ("chair", "office"): "office_chair",
               ("chair", "four_legged"): "dining_chair"}


def judged(obj: dict) -> dict:
    """An accepted object as judged: of the furniture class it is or specializes (a coffee_table is
    a table, by its "is_a"), its own model kept as "concept"."""
    names = [obj["model"], *obj.get("is_a", [])]
    cls = next((n for n in names if n in FURNITURE + NOT_FURNITURE + ("sofa",)), obj["model"])
    return dict(obj, model=cls, concept=obj["model"])
# the part whose size is judged: as found (any of these roles: a cabinet's modalities name its
# face differently) and in the renderer's truth
SIZED_PARTS = {"table": ("top",), "chair": ("seat",), "door": ("leaf",), "cabinet": ("face", "front")}
TRUE_PART = {"table": "top", "chair": "seat", "door": "leaf", "cabinet": "body"}


def true_sizes(model: str, part: dict) -> tuple[float, float]:
    """The (longer, shorter) side of a truth part's face: a box's two largest extents."""
    a, b = sorted(part["world"]["size"], reverse=True)[:2]
    return a, b


def found_sizes(obj: dict) -> tuple[float, float] | None:
    p = next((obj["parts"][r] for r in SIZED_PARTS[obj["model"]] if r in obj["parts"]), None)
    return None if p is None else (max(p["size_u"], p["size_v"]), min(p["size_u"], p["size_v"]))


def in_view(obj: dict, intrinsics: dict) -> float:
    """The share of an object's projected box (its parts' corners in the camera frame) inside the
    image: what the image border cuts off is hidden too."""
    corners = []
    for p in obj["parts"]:
        c = p["camera"]
        if "size" not in c or "axis2" not in c:
            continue
        a, b = np.asarray(c["axis"]), np.asarray(c["axis2"])
        e = np.stack([b, np.cross(a, b), a])  # local x, y, z
        half = np.asarray(c["size"]) / 2
        signs = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)])
        corners.append(np.asarray(c["center"]) + (signs * half) @ e)
    if not corners:
        return 1.0
    pts = np.concatenate(corners)
    pts = pts[pts[:, 2] > 0.05]
    if len(pts) == 0:
        return 0.0
    u = intrinsics["fx"] * pts[:, 0] / pts[:, 2] + intrinsics["cx"]
    v = intrinsics["fy"] * pts[:, 1] / pts[:, 2] + intrinsics["cy"]
    u0, u1, v0, v1 = u.min(), u.max(), v.min(), v.max()
    area = max(1e-9, (u1 - u0) * (v1 - v0))
    iw = max(0.0, min(u1, intrinsics["width"]) - max(u0, 0.0))
    ih = max(0.0, min(v1, intrinsics["height"]) - max(v0, 0.0))
    return iw * ih / area


def rendered(args) -> int:
    import mereo

    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    graph = room_graph(args.set)
    so = mereo.synthetic.SceneOptions(room=True, depth_model=args.depth_model)
    tp = {c: 0 for c in FURNITURE}
    need = {c: 0 for c in FURNITURE}
    accepted = {c: 0 for c in FURNITURE}
    errors = {c: [] for c in FURNITURE}
    whole = {c: [] for c in FURNITURE}  # the same for parts seen whole (99%: nothing of them hidden)
    door_kinds = {}
    specialized = {}  # (model, kind) -> [right, generic, wrong]
    times = []
    for seed in range(args.first, args.first + args.rendered):
        sf = mereo.synthetic.render(seed, so)
        truth = json.loads(sf.truth_json())
        by_id = {o["id"]: o for o in truth["objects"]}
        t0 = time.perf_counter()
        result, segments = run(graph, sf.frame)
        times.append(1000 * (time.perf_counter() - t0))
        ids = np.asarray(sf.truth.objects)
        shape = ids.shape
        matched, line = {}, []
        for o in [judged(o) for o in result["objects"] if o["accepted"]]:
            if o["model"] in NOT_FURNITURE:
                continue
            m = object_mask(o, segments, shape)
            accepted[o["model"]] = accepted.get(o["model"], 0) + 1
            hit = ids[m]
            hit = hit[hit > 0]
            tid = int(np.bincount(hit).argmax()) if hit.size else 0
            t = by_id.get(tid)
            ok = t is not None and t["model"] == o["model"] and tid not in matched
            if ok:
                matched[tid] = o
            line.append(f"{o['model']}{'' if ok else ' (false: on ' + (t['model'] if t else 'nothing') + ')'}")
        for t in truth["objects"]:
            if t["model"] not in FURNITURE:
                continue
            share = t["visible_pixels"] / max(1, t.get("unoccluded_pixels", t["visible_pixels"]))
            share *= in_view(t, truth["intrinsics"])
            if t["model"] == "door":
                door_kinds.setdefault(t.get("kind", ""), [0, 0])
            if share < 0.4 or t["visible_pixels"] == 0:
                continue
            need[t["model"]] += 1
            if t["model"] == "door":
                door_kinds[t.get("kind", "")][1] += 1
            o = matched.get(t["id"])
            if o is None:
                line.append(f"missed {t['model']}{' ' + t.get('kind', '') if t['model'] == 'door' else ''} ({100 * share:.0f}%)")
                continue
            tp[t["model"]] += 1
            if (t["model"], t.get("kind", "")) in SPECIALIZED:
                tally = specialized.setdefault((t["model"], t["kind"]), [0, 0, 0])
                want = SPECIALIZED[(t["model"], t["kind"])]
                tally[0 if o["concept"] == want else 1 if o["concept"] == t["model"] else 2] += 1
            if t["model"] == "door":
                door_kinds[t.get("kind", "")][0] += 1
            part = next(p for p in t["parts"] if p["role"] == TRUE_PART[t["model"]])
            got = found_sizes(o)
            part_share = part["visible_pixels"] / max(1, part.get("unoccluded_pixels", part["visible_pixels"]))
            part_share *= in_view({"parts": [part]}, truth["intrinsics"])
            if got is not None and part_share >= 0.9:
                want = true_sizes(t["model"], part)
                errors[t["model"]].append((abs(got[0] - want[0]), abs(got[1] - want[1])))
                if part_share >= 0.99:
                    whole[t["model"]].append(errors[t["model"]][-1])
                if max(abs(got[0] - want[0]), abs(got[1] - want[1])) > 0.05:  # named, to be looked at
                    line.append(f"{t['model']}'s {part['role']} {got[0]:.2f} x {got[1]:.2f} m for {want[0]:.2f} x {want[1]:.2f}")
        print(f"room {seed}: {', '.join(line) or 'nothing'}")
        overlay(sf.frame, result, [], out / f"room_{seed}.png")
    print()
    for c in FURNITURE:
        prec = tp[c] / max(1, accepted[c])
        e = np.asarray(errors[c]).reshape(-1, 2)
        err = (f", size errors over {len(e)} at least 90% visible, longer / shorter side: median "
               f"{100 * np.median(e[:, 0]):.1f} / {100 * np.median(e[:, 1]):.1f} cm, "
               f"max {100 * e[:, 0].max():.1f} / {100 * e[:, 1].max():.1f} cm, "
               f"both within 5 cm {int((e.max(axis=1) <= 0.05).sum())}/{len(e)}") if len(e) else ""
        w = np.asarray(whole[c]).reshape(-1, 2)
        err += (f"; of those seen whole (99%), both within 5 cm {int((w.max(axis=1) <= 0.05).sum())}/{len(w)}, max "
                f"{100 * w[:, 0].max():.1f} / {100 * w[:, 1].max():.1f} cm") if len(w) else ""
        print(f"{c:6s} recall {tp[c]}/{need[c]} = {tp[c] / max(1, need[c]):.2f}, precision {tp[c]}/{accepted[c]} = {prec:.2f}{err}")
    for k, (a, b) in sorted(door_kinds.items()):
        print(f"doors {k}: {a}/{b}")
    for (model, kind), (right, generic, wrong) in sorted(specialized.items()):
        print(f"{model}s {kind}, found: as {SPECIALIZED[(model, kind)]} {right}, as {model} {generic}, as another {wrong}")
    print(f"ms per frame (graph run, median): {np.median(times):.0f}; overlays in {out}")
    if args.json:
        Path(args.json).write_text(json.dumps({
            "tp": tp, "need": need, "accepted": accepted, "size_errors": errors, "size_errors_whole": whole, "median_ms": float(np.median(times)),
            "specialized": {f"{m} {k}": v for (m, k), v in specialized.items()}}))
    return 0


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", default="out/eval_room", help="overlays folder")
    ap.add_argument("--json", help="write the figures here")
    ap.add_argument("--rendered", type=int, default=0, help="judge N rendered rooms instead of the real frames")
    ap.add_argument("--first", type=int, default=9100, help="the first rendered room's seed")
    ap.add_argument("--depth-model", default="kinect", choices=["kinect", "stereo"])
    ap.add_argument("--set", action="append", default=[], metavar="NODE.OPTION=VALUE",
                    help="a node option of the room graph (e.g. patches.max_angle_deg=30), for sweeps")
    args = ap.parse_args(argv)
    if args.rendered:
        return rendered(args)
    if not REAL.is_dir():
        print(f"eval_room: {REAL} is missing (the shared data beside the clone); nothing to judge")
        return 0
    import mereo

    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    graph = room_graph(args.set)
    frames = json.loads(LABELS.read_text())["frames"]
    classes = ["chair", "table", "sofa", "door", "cabinet"]
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
        objects = [judged(o) for o in result["objects"] if o["accepted"]]
        objects = [o for o in objects if o["model"] not in NOT_FURNITURE]
        found, wrong = [], []
        matched = set()
        for o, i, share in match(objects, labels, segments, shape):
            if i is None:
                fp[o["model"]] = fp.get(o["model"], 0) + 1
                wrong.append(f"{o['concept']} {o['score']:.2f}")
            else:
                matched.add(i)
                found.append(f"{o['concept']}{' (optional)' if labels[i].get('optional') else ''}")
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
