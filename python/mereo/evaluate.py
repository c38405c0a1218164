"""Evaluation of recognition results against the renderer's ground truth (`mereo evaluate`).

A result object (accepted, with a "body") is matched to the ground-truth object whose body
axis passes within `max_offset` (2 cm) of the result body's centre (a sphere: whose centre is
within 2 cm; a free-form region: whose axis passes within 2 cm and half its box's width of the
box's centre), with a radius
within `max_radius_error` (1 cm; a region has none); the nearest such object wins.
Then, per model:

- precision: accepted results of that model matched to a true object of the same model;
- recall: true objects of that model that are *eligible* (body with at least 500 visible
  pixels, a bowl's outer sphere included; a mug's handle with at least 150) and recognized as
  that model;
- errors of the matched bodies: position (result centre to true axis), radius, axis angle;
- for jars and cans: the share not reported as mugs;
- recall by kind where the ground truth tells kinds apart: a mug's handle shape ("mug/d",
  "mug/band"...), a can's or jar's pose ("can/lying");
- results on free-form distractors (model "other": blobs, bananas, drills, rounded boxes, not to
  be recognized): an accepted result that matches no true object and has a part's centre within
  `max_offset` of the box of an "other"'s visible surface; counted per frame, and false
  positives of their model.

Ground truth comes from `mereo render ... --out DIR` (DIR/NNNN_truth.json), a truth file, or
`synthetic:SEED` (rendered again, with the scene options given). Results and truths are paired
in order.
"""
from __future__ import annotations

import json
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

__all__ = ["Evaluation", "evaluate", "load_results", "load_truths", "format_table"]

MIN_BODY_PIXELS = 500
MIN_HANDLE_PIXELS = 150


def body_part(obj: dict) -> dict | None:
    """A result object's body: its "body" part, or for a part set without one (a conical bowl's
    wall) its first part; None when it has no parts (an unknown object)."""
    parts = obj.get("parts") or {}
    return parts.get("body") or next(iter(parts.values()), None)


def _text(path) -> str:
    """A file's UTF-8 text; a file that is not names itself and the byte."""
    try:
        return Path(path).read_bytes().decode("utf-8")
    except UnicodeDecodeError as e:
        raise ValueError(f"{path}: not UTF-8 text (byte {e.start}: {e.object[e.start:e.start + 1]!r})") from None


def _json(text: str, where: str):
    try:
        return json.loads(text)
    except json.JSONDecodeError as e:
        raise ValueError(f"{where}: not a JSON object ({e.msg})") from None


def load_results(path) -> list[dict]:
    """The frames of a JSON Lines file written by `mereo recognize`."""
    return [_json(line, f"{path}:{n}") for n, line in enumerate(_text(path).splitlines(), 1) if line.strip()]


def load_truths(specs, options=None) -> list[dict]:
    """Ground truths from truth files, folders of NNNN_truth.json, or synthetic:SEED[:FRAMES]
    (rendered with `options`, a mereo.synthetic.SceneOptions; the default scene without)."""
    from . import synthetic

    options = options if options is not None else synthetic.SceneOptions()
    out = []
    for spec in specs:
        spec = str(spec)
        if spec.startswith("synthetic:"):
            parts = spec.split(":")
            seed, frames = int(parts[1]), int(parts[2]) if len(parts) > 2 else 1
            scene = synthetic.generate_scene(seed, options)
            for i in range(frames):
                out.append(json.loads(synthetic.render_view(scene, i, options).truth_json()))
            continue
        p = Path(spec)
        if p.is_dir():
            files = sorted(p.glob("*_truth.json"))
            if not files:
                raise FileNotFoundError(f"{p}: no *_truth.json files")
            out += [_json(_text(f), str(f)) for f in files]
        else:
            out.append(_json(_text(p), str(p)))
    return out


@dataclass
class ModelStats:
    results: int = 0           # accepted results of this model
    correct: int = 0           # ... matched to a true object of this model
    eligible: int = 0          # true objects of this model that count for recall
    found: int = 0             # ... recognized as this model
    position_mm: list = field(default_factory=list)
    radius_mm: list = field(default_factory=list)
    axis_deg: list = field(default_factory=list)

    @property
    def precision(self) -> float:
        return self.correct / self.results if self.results else math.nan

    @property
    def recall(self) -> float:
        return self.found / self.eligible if self.eligible else math.nan


@dataclass
class Evaluation:
    frames: int = 0
    models: dict = field(default_factory=dict)   # model -> ModelStats
    kinds: dict = field(default_factory=dict)    # "model/kind" -> ModelStats (eligible, found)
    jars_cans: int = 0                           # true jars and cans (eligible)
    jars_cans_as_mugs: int = 0
    others: int = 0                              # free-form distractors ("other") in view
    on_others: list = field(default_factory=list)  # per frame: accepted results on them
    mistakes: list = field(default_factory=list)  # "frame: what"

    @property
    def jars_cans_not_mugs(self) -> float:
        return 1 - self.jars_cans_as_mugs / self.jars_cans if self.jars_cans else math.nan

    @property
    def on_others_per_frame(self) -> float:
        return sum(self.on_others) / self.frames if self.frames else math.nan

    def summary(self) -> dict:
        out = {"frames": self.frames, "jars_cans": self.jars_cans,
               "jars_cans_not_mugs": self.jars_cans_not_mugs,
               "others": self.others, "on_others": sum(self.on_others),
               "on_others_per_frame": self.on_others_per_frame, "on_others_by_frame": list(self.on_others),
               "kinds": {name: {"eligible": s.eligible, "found": s.found, "recall": s.recall}
                         for name, s in sorted(self.kinds.items())},
               "models": {}}
        for name, s in sorted(self.models.items()):
            out["models"][name] = {
                "results": s.results, "precision": s.precision, "eligible": s.eligible, "recall": s.recall,
                "median_position_mm": float(np.median(s.position_mm)) if s.position_mm else math.nan,
                "median_radius_mm": float(np.median(s.radius_mm)) if s.radius_mm else math.nan,
                "median_axis_deg": float(np.median(s.axis_deg)) if s.axis_deg else math.nan,
            }
        return out


def _body(parts: list[dict], cls: str = "cylinder"):
    """A true object's body of class `cls` (a free-form "region" stands for a body of any class)."""
    for p in parts:
        if p["role"] == "body" and (p["class"] == cls or cls == "region"):
            return p
    return None


def _match(result_body: dict, truths: list[dict], max_offset: float, max_radius_error: float):
    """The true object whose body is nearest the result's body (a cylinder: its axis passes
    nearest the result's centre; a sphere: its centre; a free-form region: its box's centre
    near any body's axis, no radius to compare), within limits."""
    sphere = result_body["class"] == "sphere"
    region = result_body["class"] == "region"
    c = np.asarray(result_body["center" if sphere else "point"])
    # a region's box holds the visible side only: its centre lies up to half its extent in front
    # of the axis
    limit = max_offset + (max(result_body["width"], result_body["thickness"]) / 2 if region else 0)
    best, best_d = None, math.inf
    for t in truths:
        b = _body(t["parts"], result_body["class"])
        if b is None or (region and b["class"] == "sphere"):
            continue
        cam = b["camera"]
        p, a = np.asarray(cam.get("point", cam.get("center"))), np.asarray(cam["axis"]) / np.linalg.norm(cam["axis"])
        q = c - p
        d = np.linalg.norm(q) if sphere else np.linalg.norm(q - a * q.dot(a))
        within = sphere or abs(q.dot(a)) <= cam["height"]
        radius_ok = region or abs(result_body["radius"] - cam["radius"]) <= max_radius_error
        if d <= min(limit, best_d) and radius_ok and within:
            best, best_d = t, d
    return best, best_d


def _centres(result: dict):
    """The centres of a result's parts (cylinders' points, tori's and spheres' centres)."""
    for p in result["parts"].values():
        c = p.get("point", p.get("center"))
        if c is not None and len(c) == 3:
            yield np.asarray(c, dtype=float)


def _on_other(result: dict, others: list[dict], max_offset: float):
    """The "other" object whose visible box (grown by max_offset) holds a centre of the result."""
    for t in others:
        box = t.get("visible_box")
        if box is None:
            continue
        lo, hi = np.asarray(box["min"]) - max_offset, np.asarray(box["max"]) + max_offset
        if any(np.all(c >= lo) and np.all(c <= hi) for c in _centres(result)):
            return t
    return None


def _kind(t: dict) -> str:
    """What tells a true object's kind apart: a mug's handle shape, a can's or jar's pose."""
    return t.get("kind") or t.get("pose") or ""


def evaluate(results: list[dict], truths: list[dict], max_offset: float = 0.02,
             max_radius_error: float = 0.01) -> Evaluation:
    if len(results) != len(truths):
        raise ValueError(f"{len(results)} result frames but {len(truths)} ground truths: they are paired in order")
    ev = Evaluation(frames=len(results))
    for res, truth in zip(results, truths):
        tag = f'{truth.get("source", "")}#{truth.get("frame", "")}'
        objects = [o for o in truth["objects"] if o["model"] not in ("floor", "wall", "table", "other")]
        others = [o for o in truth["objects"] if o["model"] == "other" and o["visible_pixels"] > 0]
        ev.others += len(others)
        ev.on_others.append(0)
        claimed: dict[int, str] = {}  # true object id -> model claimed
        for o in res["objects"]:
            if not o.get("accepted", True):
                continue
            s = ev.models.setdefault(o["model"], ModelStats())
            s.results += 1
            body = body_part(o)
            t = None
            if body is not None and body["class"] in ("cylinder", "cone", "sphere", "region"):
                t, d = _match(body, objects, max_offset, max_radius_error)
            if t is None:
                other = _on_other(o, others, max_offset)
                if other is not None:
                    ev.on_others[-1] += 1
                    ev.mistakes.append(f"{tag}: {o['model']} {o['score']:.2f} on the {other.get('kind', 'other')} "
                                       f"{other['id']} (a free-form distractor)")
                else:
                    ev.mistakes.append(f"{tag}: {o['model']} {o['score']:.2f} matches no object")
                continue
            claimed[t["id"]] = o["model"]
            if t["model"] != o["model"]:
                ev.mistakes.append(f"{tag}: the {t['model']} {t['id']} taken for a {o['model']} ({o['score']:.2f})")
                continue
            s.correct += 1
            cam = _body(t["parts"], body["class"])["camera"]
            s.position_mm.append(1000 * d)
            if "radius" in body:  # (a free-form region has none)
                s.radius_mm.append(1000 * abs(body["radius"] - cam["radius"]))
            if body["class"] in ("cylinder", "cone"):
                a = np.asarray(cam["axis"]) / np.linalg.norm(cam["axis"])
                cosang = abs(float(np.dot(a, np.asarray(body["axis"]) / np.linalg.norm(body["axis"]))))
                s.axis_deg.append(math.degrees(math.acos(min(1.0, cosang))))
        for t in objects:
            b = _body(t["parts"]) or _body(t["parts"], "cone") or _body(t["parts"], "sphere")
            if b is None or b["visible_pixels"] < MIN_BODY_PIXELS:
                continue
            if t["model"] == "mug":
                h = [p for p in t["parts"] if p["role"] == "handle"]
                if not h or h[0]["visible_pixels"] < MIN_HANDLE_PIXELS:
                    continue
            s = ev.models.setdefault(t["model"], ModelStats())
            k = ev.kinds.setdefault(f"{t['model']}/{_kind(t)}", ModelStats()) if _kind(t) else None
            s.eligible += 1
            if k is not None:
                k.eligible += 1
            if claimed.get(t["id"]) == t["model"]:
                s.found += 1
                if k is not None:
                    k.found += 1
            else:
                ev.mistakes.append(f"{tag}: the {t['model']} {t['id']} is missed"
                                   + (f" (taken for a {claimed[t['id']]})" if t["id"] in claimed else ""))
            if t["model"] in ("jar", "can"):
                ev.jars_cans += 1
                ev.jars_cans_as_mugs += claimed.get(t["id"]) == "mug"
    return ev


def format_table(ev: Evaluation) -> str:
    def f(v, fmt):
        return "-" if isinstance(v, float) and math.isnan(v) else format(v, fmt)

    lines = [f"{ev.frames} frames",
             f"{'model':<10} {'results':>8} {'precision':>10} {'eligible':>9} {'recall':>8} "
             f"{'pos mm':>8} {'radius mm':>10} {'axis deg':>9}"]
    for name, s in sorted(ev.summary()["models"].items()):
        lines.append(f"{name:<10} {s['results']:>8} {f(s['precision'], '.3f'):>10} {s['eligible']:>9} "
                     f"{f(s['recall'], '.3f'):>8} {f(s['median_position_mm'], '.1f'):>8} "
                     f"{f(s['median_radius_mm'], '.2f'):>10} {f(s['median_axis_deg'], '.2f'):>9}")
    lines.append(f"jars and cans not reported as mugs: {ev.jars_cans - ev.jars_cans_as_mugs}/{ev.jars_cans} "
                 f"({f(ev.jars_cans_not_mugs, '.3f')})")
    if ev.kinds:
        lines.append("recall by kind: " + ", ".join(f"{name} {s.found}/{s.eligible}" for name, s in sorted(ev.kinds.items())))
    if ev.others:
        lines.append(f"accepted objects on free-form distractors: {sum(ev.on_others)} "
                     f"({f(ev.on_others_per_frame, '.2f')} per frame; {ev.others} distractors in view)")
    return "\n".join(lines)
