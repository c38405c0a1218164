"""The object layer from Python: models from YAML and from Python (with a Python predicate),
matching (branch and bound = exhaustive), the lattice, errors, and the match_models node."""
from pathlib import Path

import numpy as np
import pytest

import mereo
from mereo import knowledge as kn

ROOT = Path(__file__).resolve().parents[2]
UP = np.array([0.0, -1.0, 0.0])


def mug_segments():
    body = kn.Segment("cylinder", point=[0, 0, 1], axis=UP, radius=0.04, height=0.1)
    handle = kn.Segment("torus", point=[0.04 + 0.6 * 0.025, 0, 1], axis=[0, 0, 1], radius=0.025, minor_radius=0.006)
    jar = kn.Segment("cylinder", point=[0.3, 0, 1], axis=UP, radius=0.05, height=0.14)
    ring = kn.Segment("torus", point=[0.3 + 0.05 + 0.02 + 0.006 + 0.025, 0, 1], axis=[0, 0, 1], radius=0.025,
                      minor_radius=0.006)  # a handle-like ring standing 2 cm beside the jar
    return [body, handle, jar, ring]


def test_shipped_models_and_matching():
    kb = kn.load_models()
    assert {"mug", "jar", "can", "bottle", "plate", "bowl", "cup"} <= set(kb.names())
    mug = kb.resolve("mug")
    hyps, stats = kn.match(mug, mug_segments(), best=5, up=UP)
    # body, handle; the optional inner wall (a cylinder, or a cone: inside_tapered) is not given
    assert hyps[0].assignment == [0, 1, -1, -1]
    assert hyps[0].score >= 0.9 * 0.9 and hyps[0].posterior > 0.9
    assert all(h.assignment[0] != 2 for h in hyps)  # the jar with the ring beside it is no mug
    ex, ex_stats = kn.match(mug, mug_segments(), best=5, up=UP, exhaustive=True)
    assert [(h.assignment, h.score) for h in ex] == [(h.assignment, h.score) for h in hyps]
    lattice = kn.recognize(kb, ["mug", "jar", "cup"], mug_segments(), up=UP)
    names = {h.concept for h in lattice.hypotheses}
    assert names == {"mug", "jar", "cup"}
    for i, j in lattice.excludes:
        a, b = lattice.hypotheses[i].assignment, lattice.hypotheses[j].assignment
        assert set(x for x in a if x >= 0) & set(x for x in b if x >= 0)



def test_every_modality_of_a_concept_is_matched_and_named():
    """The shipped bowl has two part sets (round: a sphere; conical: a cone's inner wall): both are
    looked for, and each hypothesis names the one it was matched with."""
    kb = kn.load_models()
    sphere = kn.Segment("sphere", point=[0, 0, 1], radius=0.08)
    wall = kn.Segment("cone", point=[0.3, 0, 1], axis=UP, radius=0.06, half_angle_deg=30, height=0.05, inward=True)
    jar = mug_segments()[2]
    lattice = kn.recognize(kb, ["bowl", "jar"], [sphere, wall, jar], up=UP)
    got = {(h.concept, h.modality, tuple(h.assignment)) for h in lattice.hypotheses if h.score > 0.5}
    assert ("bowl", "round", (0, -1)) in got and ("bowl", "conical", (1,)) in got, got
    assert ("jar", "", (2, -1)) in got, got
    # a tapered cup's wall (8 degrees) is no bowl
    cup_wall = kn.Segment("cone", point=[0.3, 0, 1], axis=UP, radius=0.06, half_angle_deg=8, height=0.05, inward=True)
    lattice = kn.recognize(kb, ["bowl"], [cup_wall], up=UP)
    assert all(h.score < 0.5 for h in lattice.hypotheses if h.modality == "conical")

def test_python_concept_with_a_python_predicate():
    calls = []

    def level(segments, constraint, context):  # the two parts' centres at the same height
        calls.append(1)
        a, b = segments
        return float(abs(np.dot(np.asarray(a.point) - np.asarray(b.point), context.up)) < 0.02)

    kb = kn.load_models()
    kb.add(kn.concept("twin_jars", parts={"left": "cylinder", "right": ("cylinder", {"group": "pair"}),
                                          "third": ("cylinder", {"optional": True, "missing_score": 0.5})},
                      attributes={"left.radius": (0.03, 0.06, 0.005), "right.radius": (0.03, 0.06, 0.005)},
                      constraints=[("level", level, "left", "right"), ("same_size", "left", "right", {"ratio": 0.7})]))
    c = kb.resolve("twin_jars")
    hyps, _ = kn.match(c, mug_segments(), best=3, up=UP)
    assert calls and hyps and sorted(hyps[0].assignment[:2]) == [0, 2]


def test_model_file_errors_name_file_line_and_field(tmp_path):
    with pytest.raises(mereo.InputError, match=r"model_typo.yaml:9:\d+: field 'maxx'"):
        kn.load_models(ROOT / "tests/data/model_typo.yaml")
    with pytest.raises(mereo.InputError, match=r"model_unknown_class.yaml:5:\d+: field 'class': unknown class 'toroid'"):
        kn.load_models(ROOT / "tests/data/model_unknown_class.yaml")
    with pytest.raises(mereo.InputError, match="unknown predicate 'touches'"):
        kb = kn.load_models()
        kb.add(kn.concept("x", parts={"a": "cylinder", "b": "torus"}, constraints=[("touches", "a", "b")]))
        kb.resolve("x")


def test_match_models_node_in_a_graph():
    g = mereo.Graph()
    src = g.add("frame_source", "source")
    g.add_python(lambda frame: mug_segments(), "segments", inputs=[("frame", "Frame")], outputs=[("segments", "Segments")])
    models = g.add(mereo.nodes.models(models="mug, jar"), "models")
    objects = g.add(mereo.nodes.match_models(best=3), "objects")
    g.connect(src.frame, "segments.frame")
    g.connect("segments.segments", objects.segments)
    g.connect(models.models, objects.models)
    frame = mereo.synthetic.render(1).frame
    frame.pose = None  # no pose: "up" is the camera's -y, as the segments assume
    (r,) = g.run([frame], keep=["objects.lattice"])
    lattice = r["outputs"]["objects.lattice"]
    best_mug = [h for h in lattice.hypotheses if h.concept == "mug"][0]
    assert best_mug.assignment == [0, 1, -1]  # body, handle (no inner wall given)
    bad = mereo.Graph()
    bad.add("frame_source", "source")
    bad.add_python(lambda frame: mug_segments(), "segments", inputs=[("frame", "Frame")],
                   outputs=[("segments", "Segments")])
    bad.add(mereo.nodes.models(models="mugg"), "models")
    bad.add(mereo.nodes.match_models(), "objects")
    bad.connect("source.frame", "segments.frame")
    bad.connect("segments.segments", "objects.segments")
    bad.connect("models.models", "objects.models")
    with pytest.raises(mereo.GraphError, match="node 'models' \\(models\\): unknown concept 'mugg'"):
        bad.verify()
