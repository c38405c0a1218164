"""Recognition: the tabletop pipeline (``graphs/tabletop.yaml``) from Python.

    import mereo
    result = mereo.recognize(mereo.io.read("synthetic:7"), models=["mug"])
    for obj in result["objects"]:
        if obj["accepted"]:
            print(obj["model"], obj["score"], obj["parts"]["body"]["radius"])

``result`` is the dict of one line of ``mereo recognize``'s JSON Lines output (DESIGN.md). The
numeric work is the graph's (C++); this module only builds the graph, runs it and reads its
JSON result.
"""
from __future__ import annotations

import json
from pathlib import Path
from typing import Iterable, Iterator, Sequence

import numpy as np

from . import _mereo
from ._mereo import Graph
from ._mereo.io import colorize_depth, draw_objects
from ._mereo.knowledge import Segment

__all__ = [
    "GRAPH_DIR",
    "draw_result",
    "goal_options",
    "recognize",
    "recognize_all",
    "segment_from_dict",
    "tabletop_graph",
]

#: The installed pipeline files (a copy of the repository's graphs/*.yaml).
GRAPH_DIR = Path(__file__).parent / "graphs"
_SOURCE_GRAPHS = Path(__file__).resolve().parents[2] / "graphs"


def _graph_path(name: str) -> Path:
    for d in (GRAPH_DIR, _SOURCE_GRAPHS):
        if (d / name).is_file():
            return d / name
    raise FileNotFoundError(f"{name}: not found in {GRAPH_DIR}")


def goal_options(goal: str | None, models_file: str = "") -> dict:
    """Options of the detect_primitives node for a goal (the top-down rule): the primitive classes
    the goal's parts need, and a handle search only next to cylinders that could be its body."""
    if not goal:
        return {}
    from .knowledge import load_models

    kb = load_models(models_file or None)
    concept = kb.resolve(goal)
    classes = sorted({p.cls for p in concept.parts})
    opts = {"classes": ",".join(c for c in classes if c in ("plane", "cylinder", "sphere", "torus"))}
    if "torus" not in classes:
        opts["handles_near_cylinders"] = False
    # the handle search only next to the cylinders that could be the goal's body
    for a in concept.attributes:
        if a.part == "body" and a.name == "radius":
            opts["handle_body_min_radius"] = max(0.0, a.range.a)
            opts["handle_body_max_radius"] = a.range.d
    return opts


def tabletop_graph(models: Sequence[str] | str | None = None, *, goal: str | None = None,
                   models_file: str = "", graph: str | Path | None = None, tracking: bool = False,
                   odometry: bool = False) -> Graph:
    """The tabletop pipeline (or the graph file `graph`, or a shipped graph by name: "room"), with
    the models to look for (names of concepts; default all the file's) and an optional goal that
    restricts them and drives the
    top-down search (``goal="mug"``: the models become ["mug"], primitives the mug's classes).
    With `tracking`, the pipeline of ``tabletop_tracking.yaml``: hypotheses held across the
    frames of a sequence (the frames' poses; with `odometry`, ``tabletop_odometry.yaml``: poses
    estimated from the frames), each reported object with its "track" id."""
    name = "tabletop_odometry.yaml" if tracking and odometry else "tabletop_tracking.yaml" if tracking else "tabletop.yaml"
    if graph and not Path(graph).exists() and Path(graph).suffix == "" and "/" not in str(graph):
        graph = _graph_path(f"{graph}.yaml")  # a shipped graph by name: "room" is graphs/room.yaml
    g = Graph.load(str(graph) if graph else str(_graph_path(name)))
    # what this function and `mereo recognize` use of the graph: the node "result" whose output
    # "result" is the JSON result, and the node "models" that the models and goal configure
    nodes = {n.name: n for n in g.nodes}
    needs = [("result", "result", "report")] + ([("models", "models", "models")] if models or goal or models_file else [])
    for node, port, kind in needs:
        if node not in nodes or port not in nodes[node].outputs:
            raise _mereo.InputError(
                f"{graph or name}: the graph has no node '{node}' with an output '{port}' (a '{kind}' node; "
                f"its nodes: {', '.join(f'{n.name} ({n.kind})' for n in g.nodes)})")
    if isinstance(models, str):
        models = [m.strip() for m in models.split(",") if m.strip()]
    if goal:
        models = [goal]
        g.set_options("primitives", **goal_options(goal, models_file))
    # the graph's one models node: the concepts looked for and the model file
    options = {"models": ",".join(models)} if models else {}
    if models_file:
        options["file"] = str(models_file)
    if options:
        g.set_options("models", **options)
    g.verify()
    return g


def _result(r: dict, on_error: str = "stop") -> dict:
    """One frame's result dict from a run's result. A node that failed on the frame (its content:
    no support surface in view, too little depth...) raises with on_error="stop"; with "skip" the
    frame gets an empty result whose "warnings" say which node failed and why (DESIGN.md), so that
    a sequence goes on. (A frame that cannot be read stops the run either way.)"""
    times = dict(r["timings_ms"])
    times["total"] = sum(times.values())
    if r["error"]:
        if on_error != "skip":
            raise _mereo.InputError(r["error"])
        return {"frame": r["frame"], "source": "", "objects": [], "primitives": [],
                "warnings": [f"{r['error_node']}: {r['error_cause']}"], "timing_ms": times}
    out = json.loads(r["outputs"]["result.result"])
    out["timing_ms"] = times
    return out


def recognize_all(frames, *, graph: Graph | None = None, models: Sequence[str] | str | None = None,
                  goal: str | None = None, mode: str = "parallel", on_result=None,
                  on_error: str = "skip") -> Iterator[dict] | None:
    """Runs the pipeline over frames (a list, a mereo.io.Sequence); returns the results in frame
    order, or passes each to `on_result(result)` as it comes (then returns None). A frame where a
    node finds nothing usable gets an empty result with "warnings" and the run goes on
    (on_error="stop": the first such frame raises)."""
    if on_error not in ("skip", "stop"):
        raise ValueError(f"on_error '{on_error}' is not 'skip' or 'stop'")
    g = graph or tabletop_graph(models, goal=goal)
    run = dict(mode=mode, keep=["result.result"], on_error=on_error)
    if on_result is not None:
        g.run(frames, on_result=lambda r: on_result(_result(r, on_error)), **run)
        return None
    return [_result(r, on_error) for r in g.run(frames, **run)]


def recognize(frame, models: Sequence[str] | str | None = None, *, goal: str | None = None,
              graph: Graph | None = None, on_error: str = "skip") -> dict:
    """Recognizes the objects of one frame: the same dict as one line of `mereo recognize` (with
    "warnings" and no objects when a node found nothing usable; on_error="stop" raises then)."""
    return recognize_all([frame], graph=graph, models=models, goal=goal, mode="deterministic", on_error=on_error)[0]


def segment_from_dict(d: dict) -> Segment:
    """A Segment from a part or primitive of a result (for drawing or for the matcher)."""
    s = Segment.from_dict(d)
    s.inliers = d.get("inliers", 0)
    return s


def draw_result(frame, result: dict, accepted_only: bool = True) -> np.ndarray:
    """The frame's colour image (its depth in false colour when it has none) with the recognized
    objects drawn (part outlines, model, score), and the unknown objects (regions no model
    explains) as grey boxes. A tracked object not seen in this frame (`"in_view": false`) is not
    drawn: its place is a prediction, often outside the image."""
    objects, boxes = [], []
    for o in result["objects"]:
        if "region" in o:
            boxes.append(("unknown", tuple(o["region"]["box"])))
        elif o.get("in_view") is False:
            continue
        elif o["accepted"] or not accepted_only:
            objects.append((f'{o["model"]} {o["score"]:.2f}', [segment_from_dict(p) for p in o["parts"].values()]))
    color = frame.color
    if color is None or color.size == 0:
        color = colorize_depth(np.ascontiguousarray(frame.depth, dtype=np.float32))
    return draw_objects(color, frame.intrinsics, objects, boxes)
